"""Self-collision: the continuous-joint sweep, default-pose contacts and the collision matrix.

Built on :mod:`geomcheck.kinematics` (forward kinematics) and :mod:`geomcheck.collision`
(engines and the collision scene); the check families in :mod:`geomcheck.checks` run them.
"""
