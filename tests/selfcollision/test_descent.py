"""Newton descent of a pair's distance: the analytic gradient and the descent itself."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from geomcheck.collision import CollisionScene, get_backend
from geomcheck.kinematics import Kinematics
from geomcheck.load import MeshStore, load_description, make_bundle
from geomcheck.selfcollision.descent import PairDistance, descend
from geomcheck.selfcollision.paths import pair_path

# Two branches off a base: a shoulder (revolute about z) carrying a forearm that slides along
# its x axis and turns about its own y axis, its geometry offset from the joints; and a wrist
# turning about a tilted axis, with a follower that mimics it at twice the angle. The gradient
# of the distance between the forearm and the follower involves every kind of step; both are
# boxes, whose nearest points the engines find exactly.
CHAIN = """<?xml version="1.0"?>
<robot name="chain">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <link name="upper"/>
  <joint name="slide" type="prismatic"><parent link="upper"/><child link="carriage"/>
    <origin xyz="0.1 0 0"/><axis xyz="1 0 0"/><limit lower="0" upper="0.3" effort="1" velocity="1"/></joint>
  <link name="carriage"/>
  <joint name="elbow" type="revolute"><parent link="carriage"/><child link="forearm"/>
    <origin xyz="0.05 0 0" rpy="0.3 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <link name="forearm">
    <collision><origin xyz="0.15 0.02 0" rpy="0 0.4 0"/><geometry><box size="0.3 0.04 0.03"/></geometry></collision>
  </link>
  <joint name="wrist" type="revolute"><parent link="base"/><child link="hand"/>
    <origin xyz="-0.3 0.2 0.25"/><axis xyz="0.3 1 0.2"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <link name="hand"/>
  <joint name="follow" type="revolute"><parent link="hand"/><child link="follower"/>
    <origin xyz="0 0.1 0"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
    <mimic joint="wrist" multiplier="2" offset="0.1"/></joint>
  <link name="follower">
    <collision><origin xyz="0 0.1 0.05" rpy="0.2 0 0.5"/><geometry><box size="0.06 0.05 0.2"/></geometry></collision>
  </link>
</robot>
"""

# An arm whose 1 cm tip ball turns about z at 0.5 m; a 2 cm post ball that the tip grazes by
# 0.05 mm at 1 rad only (a window of about +-3.5 mrad), and a stop ball 10 cm past it.
GRAZE = 0.5 + 0.03 - 0.00005  # post distance from the axis [m]
ARM = f"""<?xml version="1.0"?>
<robot name="arm">
  <link name="base"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
  <joint name="swing" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-0.5" upper="{{upper}}" effort="1" velocity="1"/></joint>
  <link name="arm"><collision><origin xyz="0.5 0 0"/><geometry><sphere radius="0.01"/></geometry></collision></link>
  <joint name="post_mount" type="fixed"><parent link="base"/><child link="post"/>
    <origin xyz="{GRAZE * math.cos(1.0):.9f} {GRAZE * math.sin(1.0):.9f} 0"/></joint>
  <link name="post"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
</robot>
"""


def _load(tmp_path: Path, text: str, backend: str = "coal") -> tuple[Kinematics, CollisionScene]:
    (tmp_path / "robot.urdf").write_text(text)
    bundle = make_bundle(tmp_path / "robot.urdf")
    loaded = load_description(bundle)
    return Kinematics(loaded.robot), CollisionScene(loaded.robot, MeshStore(bundle), get_backend(backend))


class _Found(Exception):
    pass


def test_gradient_matches_finite_differences(tmp_path: Path) -> None:
    kin, scene = _load(tmp_path, CHAIN)
    _, fcl_scene = _load(tmp_path, CHAIN, "fcl")
    path = pair_path(kin, "forearm", "follower")
    variables = np.array(path.variables)
    assert [kin.joints[v].name for v in variables] == ["shoulder", "slide", "elbow", "wrist"]
    distance = PairDistance(scene, ("forearm", "follower"), path, variables)
    fcl_distance = PairDistance(fcl_scene, ("forearm", "follower"), path, variables)
    rng = np.random.default_rng(3)
    step, checked = 1e-6, 0
    for _ in range(40):
        q = kin.sample(1, rng)[0]
        d, gradient, _, _ = distance.measure(q, hull=True)
        if d < 0.01:
            continue
        assert gradient is not None
        numeric = []
        for v in variables:
            up, down = q.copy(), q.copy()
            up[v] += step
            down[v] -= step
            numeric.append((distance.measure(up, True)[0] - distance.measure(down, True)[0]) / (2 * step))
        np.testing.assert_allclose(gradient, numeric, atol=1e-5, rtol=0)
        # python-fcl's GJK is too noisy for finite differences; its nearest points give the same gradient
        fcl_gradient = fcl_distance.measure(q, hull=True)[1]
        assert fcl_gradient is not None
        np.testing.assert_allclose(fcl_gradient, gradient, atol=0.02, rtol=0)
        checked += 1
    assert checked >= 15


class _ArmRig:
    """The ARM robot with its swing stopped at ``upper`` [rad]: ``measure`` for :func:`descend`
    records every swing angle it is asked about in ``seen`` and, when ``stop``, raises
    :class:`_Found` with the angle as soon as the arm touches the post."""

    def __init__(self, tmp_path: Path, upper: float, backend: str = "coal", stop: bool = True) -> None:
        self.kin, self.scene = _load(tmp_path, ARM.format(upper=upper), backend)
        path = pair_path(self.kin, "arm", "post")
        self.variables = np.array(path.variables)
        self.distance = PairDistance(self.scene, ("arm", "post"), path, self.variables)
        self.stop = stop
        self.seen: list[float] = []

    def measure(self, q: np.ndarray, hull: bool) -> tuple[float, np.ndarray | None]:
        self.seen.append(float(q[self.variables[0]]))
        d, gradient, ta, tb = self.distance.measure(q, hull)
        if self.stop and self.scene.pair_collide("arm", ta, "post", tb)[0]:
            raise _Found(self.seen[-1])
        return d, gradient

    def descend_from(self, angle: float) -> np.ndarray | None:
        self.seen.clear()
        q = self.kin.default_configuration()
        q[self.variables[0]] = angle
        v = self.variables
        return descend(self.measure, q, v, self.kin.lower[v], self.kin.upper[v], True, 0.002)


@pytest.mark.parametrize("backend", ["coal", "fcl"])
def test_descent_finds_a_contact_narrower_than_any_sampling(tmp_path: Path, backend: str) -> None:
    rig = _ArmRig(tmp_path, 2.0, backend)
    for start in (0.2, 1.7, -0.5):  # below, above, and at the lower limit
        with pytest.raises(_Found) as found:
            rig.descend_from(start)
        angle = found.value.args[0]
        assert abs(angle - 1.0) < 0.0036, (start, angle)
        assert len(rig.seen) <= 12, (start, len(rig.seen))


def test_descent_stays_within_the_limits_and_gives_up(tmp_path: Path) -> None:
    rig = _ArmRig(tmp_path, 0.9, stop=False)  # the stop is 0.1 rad short of the post
    assert rig.descend_from(0.0) is None
    assert max(rig.seen) == pytest.approx(0.9) and min(rig.seen) >= -0.5
    assert len(rig.seen) <= 17
