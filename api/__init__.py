"""The geomcheck HTTP service (FastAPI): imports the library, never the reverse."""
