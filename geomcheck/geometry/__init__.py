"""Geometry in numpy: shapes as meshes in the link frame, fit metrics, silhouettes."""
