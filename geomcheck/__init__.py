"""geomcheck: collision and geometry verification for robot descriptions (URDF and xacro).

The library is a pipeline: ``load`` (bundle, packages, xacro, URDF, meshes) builds the
typed ``model``; ``kinematics``, ``collision`` and ``geometry`` compute; ``checks`` turn
results into diagnostics of the rules in ``rules``; ``report`` renders one report model.
"""

__version__ = "0.1.0"
