"""Rules of this family: declared here with their documentation."""
