"""Forward kinematics of a :class:`~geomcheck.model.Robot`, vectorised over configurations.

A configuration is a vector of joint values ([rad] for revolute and continuous joints, [m]
for prismatic ones), one per *variable*: a moving joint that is not a mimic. Mimic joints
follow their leader (``multiplier * leader + offset``); planar and floating joints are not
variables and are held at their ``<origin>`` (a mobile base's pose in the world does not
change self-collision). Every frame is computed for a whole batch at once: the only Python
loop is over the links, each step a batched matrix product.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from geomcheck.errors import UsageError
from geomcheck.model import Joint, Robot

VARIABLE_TYPES = ("revolute", "continuous", "prismatic")
FULL_TURN = (-np.pi, np.pi)  # range of continuous joints and of revolute joints without limits [rad]


@dataclass(frozen=True)
class _Step:
    """How one frame follows from its parent: ``frame = parent @ origin @ motion(value)``."""

    frame: int  # index of the frame computed
    parent: int  # index of the parent frame
    origin: np.ndarray  # (4, 4) parent-from-joint at zero motion
    kind: str  # "fixed" | "rotation" | "translation"
    axis: np.ndarray  # (3,) unit axis in the joint frame (zero when degenerate)
    variable: int  # index in the configuration, -1 when fixed
    multiplier: float  # value = multiplier * q[variable] + offset
    offset: float

    @functools.cached_property
    def origin_turns(self) -> bool:
        """Whether ``origin`` rotates (its rotation is not exactly the identity)."""
        return not np.array_equal(self.origin[:3, :3], np.eye(3))

    @functools.cached_property
    def origin_moves(self) -> bool:
        """Whether ``origin`` translates (its translation is not exactly zero)."""
        return bool(self.origin[:3, 3].any())

    @functools.cached_property
    def skew(self) -> np.ndarray:
        """The cross-product matrix of ``axis``, (3, 3): ``skew @ v == axis x v``."""
        a = self.axis
        return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


@dataclass(frozen=True)
class FramePlacement:
    """How one frame of the tree follows from its parent: ``frame = parent @ joint.origin @
    motion(value)``, with ``value = multiplier * q[variable] + offset`` [rad or m], a rotation
    about or a translation along the unit ``axis`` (joint frame) for ``motion`` ``rotation`` or
    ``translation``; ``fixed`` (``variable`` None) when the frame does not move."""

    frame: str
    parent: str
    joint: Joint
    motion: str
    axis: np.ndarray
    variable: str | None
    multiplier: float
    offset: float


def _unit(axis: Iterable[float]) -> np.ndarray:
    a = np.asarray(tuple(axis), dtype=float)
    n = float(np.linalg.norm(a))
    return a / n if n > 0 else np.zeros(3)


def rotation_matrices(axis: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Rotations about the unit ``axis`` (3,) by ``angles`` (b,) [rad], Rodrigues' formula: (b, 3, 3)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    s = np.sin(angles)[:, None, None]
    c = np.cos(angles)[:, None, None]
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


class Kinematics:
    """Forward kinematics of a Robot, vectorised over configurations.

    ``joints`` are the configuration variables in document order; ``link_names`` the
    declared links reachable from the root, in tree order (depth first, children in
    document order). The root is the tree's top frame; when several candidates exist (a
    broken description), the one reaching most links is used and the others are left out.
    An undeclared root (the 2009 PR2's ``world``) is a frame at the identity.
    """

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        declared = set(robot.link_map)
        self.root = self._choose_root()
        frames, tree_joints = self._traverse(self.root)
        self._frame_index = {name: i for i, name in enumerate(frames)}
        self._frames = tuple(frames)
        self._tree_joints = tree_joints  # child frame name -> the joint that places it
        self.link_names: tuple[str, ...] = tuple(f for f in frames if f in declared)
        self._link_frames = np.array([self._frame_index[n] for n in self.link_names], dtype=int)
        self._link_index = {name: i for i, name in enumerate(self.link_names)}

        self._leaders = self._resolve_mimics(tree_joints.values())
        in_tree = {j.name for j in tree_joints.values()}
        leaders = {lead for lead, _, _ in self._leaders.values()}
        self.joints: tuple[Joint, ...] = tuple(
            j
            for j in robot.joints
            if j.type in VARIABLE_TYPES
            and j.name not in self._leaders
            and (j.name in in_tree or j.name in leaders)
            and robot.joint_map[j.name] is j
        )
        self._joint_index = {j.name: i for i, j in enumerate(self.joints)}
        bounds = np.array([self._bounds(j) for j in self.joints], dtype=float).reshape(-1, 2)
        self.lower: np.ndarray = bounds[:, 0]
        self.upper: np.ndarray = bounds[:, 1]
        self._steps = tuple(self._step(name, j) for name, j in tree_joints.items())
        self._step_of = dict(zip(tree_joints, self._steps, strict=True))
        self._needed_cache: dict[tuple[int, ...], tuple[_Step, ...]] = {}
        self._path_memo: dict[tuple[str, str], tuple[str, ...]] = {}  # path_joints is symmetric

    # ------------------------------------------------------------------ tree
    def _choose_root(self) -> str:
        robot = self.robot
        children = {j.child for j in robot.joints if j.child}
        candidates = [link.name for link in robot.links if link.name not in children]
        for j in robot.joints:
            if j.parent and j.parent not in robot.link_map and j.parent not in children and j.parent not in candidates:
                candidates.append(j.parent)
        if not candidates:  # every link is a child: a cycle; start from the first link
            return robot.links[0].name if robot.links else ""
        if len(candidates) == 1:
            return candidates[0]
        sizes = [sum(1 for f in self._traverse(c)[0] if f in robot.link_map) for c in candidates]
        return candidates[int(np.argmax(sizes))]  # argmax keeps the first of ties: document order

    def _traverse(self, root: str) -> tuple[list[str], dict[str, Joint]]:
        """Frames reachable from ``root`` in depth-first order, and the joint placing each one."""
        by_parent: dict[str, list[Joint]] = {}
        for j in self.robot.joints:
            if j.parent and j.child:
                by_parent.setdefault(j.parent, []).append(j)
        order: list[str] = []
        placing: dict[str, Joint] = {}
        seen = {root}
        stack = [root]
        while stack:
            name = stack.pop()
            order.append(name)
            for j in reversed(by_parent.get(name, [])):
                if j.child not in seen:
                    seen.add(j.child)
                    placing[j.child] = j
                    stack.append(j.child)
        # the stack visits children in document order but assigns the placing joint on push;
        # re-key ``placing`` in frame order so steps run parents first
        return order, {f: placing[f] for f in order if f in placing}

    def _resolve_mimics(self, joints: Iterable[Joint]) -> dict[str, tuple[str, float, float]]:
        """``{mimic joint: (leader variable, multiplier, offset)}`` with chains folded. A chain
        stops at its last valid joint (a missing or fixed leader ends it); a mimic joint in a
        cycle of mimics is left a variable of its own."""
        jm = self.robot.joint_map
        out: dict[str, tuple[str, float, float]] = {}
        for joint in joints:
            if joint.mimic is None or joint.type not in VARIABLE_TYPES:
                continue
            # value(joint) = mult * value(current) + off, walking up the chain
            mult, off, current, seen, cyclic = 1.0, 0.0, joint, {joint.name}, False
            while current.mimic is not None:
                leader = jm.get(current.mimic.joint)
                if leader is None or leader.type not in VARIABLE_TYPES:
                    break
                if leader.name in seen:
                    cyclic = True
                    break
                mult, off = mult * current.mimic.multiplier, mult * current.mimic.offset + off
                seen.add(leader.name)
                current = leader
            if current is not joint and not cyclic:
                out[joint.name] = (current.name, mult, off)
        return out

    @staticmethod
    def _bounds(joint: Joint) -> tuple[float, float]:
        if joint.type == "continuous":
            return FULL_TURN
        lim = joint.limit
        if lim is None or lim.lower is None or lim.upper is None:
            return FULL_TURN if joint.type == "revolute" else (0.0, 0.0)
        lo, hi = sorted((float(lim.lower), float(lim.upper)))
        return lo, hi

    def _step(self, frame: str, joint: Joint) -> _Step:
        variable, mult, off = -1, 1.0, 0.0
        if joint.type in VARIABLE_TYPES:
            if joint.name in self._leaders:
                leader, mult, off = self._leaders[joint.name]
                variable = self._joint_index.get(leader, -1)
            else:
                variable = self._joint_index.get(joint.name, -1)
        kind = "fixed"
        if variable >= 0:
            kind = "translation" if joint.type == "prismatic" else "rotation"
        return _Step(
            frame=self._frame_index[frame],
            parent=self._frame_index[joint.parent],
            origin=joint.origin.matrix(),
            kind=kind,
            axis=_unit(joint.axis),
            variable=variable,
            multiplier=float(mult),
            offset=float(off),
        )

    # ------------------------------------------------------------------ queries
    def index(self, joint_name: str) -> int:
        """Position of a variable joint in a configuration; :class:`UsageError` naming the valid joints."""
        try:
            return self._joint_index[joint_name]
        except KeyError:
            raise UsageError.bad_choice("joint", joint_name, [j.name for j in self.joints]) from None

    def link_index(self, link_name: str) -> int:
        """Position of a link in :attr:`link_names`; :class:`UsageError` naming the valid links."""
        try:
            return self._link_index[link_name]
        except KeyError:
            raise UsageError.bad_choice("link", link_name, self.link_names) from None

    def default_configuration(self, pose: Mapping[str, float] | None = None) -> np.ndarray:
        """The default configuration (n_joints,): 0, or mid-range where 0 is outside the
        limits, then the values of ``pose`` ({joint: [rad] or [m]}) for the joints it names."""
        q = np.where((self.lower <= 0.0) & (self.upper >= 0.0), 0.0, 0.5 * (self.lower + self.upper))
        for name, value in (pose or {}).items():
            if name in self._leaders and name not in self._joint_index:
                leader = self._leaders[name][0]
                raise UsageError(f"joint {name!r} mimics {leader!r} and cannot be posed itself; give {leader!r}")
            q[self.index(name)] = float(value)
        return q

    def sample(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """``n`` configurations drawn uniformly within the limits, shape (n, n_joints)."""
        return rng.uniform(self.lower, self.upper, size=(n, len(self.joints)))

    def link_transforms(self, q: np.ndarray, links: Iterable[str] | None = None) -> np.ndarray:
        """World-from-link transforms for configurations ``q`` (b, n_joints): (b, n_links, 4, 4),
        links in the order of :attr:`link_names`, or of ``links`` when given (only the frames on
        their paths to the root are then computed)."""
        if links is None:
            return self._frame_transforms(q, self._link_frames)
        return self._frame_transforms(
            q, np.array([self._frame_index[self.link_names[self.link_index(n)]] for n in links])
        )

    def link_rows_transforms(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """World-from-link transforms (b, len(rows), 4, 4) of the links at positions ``rows`` of
        :attr:`link_names`, for configurations ``q`` (b, n_joints); only the frames on their
        paths to the root are computed."""
        return self._frame_transforms(q, self._link_frames[np.asarray(rows, dtype=int)])

    def _frame_transforms(self, q: np.ndarray, frames: np.ndarray | None = None) -> np.ndarray:
        """Transforms (b, n_frames or len(frames), 4, 4) of all frames, or of ``frames`` (indices)."""
        q = np.asarray(q, dtype=float)
        if q.ndim != 2 or q.shape[1] != len(self.joints):
            raise ValueError(f"configurations must have shape (b, {len(self.joints)}), got {q.shape}")
        b = q.shape[0]
        wanted = np.arange(len(self._frames)) if frames is None else np.asarray(frames, dtype=int)
        needed = self._needed_steps(tuple(int(f) for f in wanted))
        # frame-major, rotation and translation apart: every product is a contiguous GEMM.
        # Products with an identity rotation or a zero translation are skipped (they would
        # return their input unchanged), and so are the temporaries of Rodrigues' formula.
        rot = np.empty((len(self._frames), b, 3, 3))
        pos = np.empty((len(self._frames), b, 3))
        root = self._frame_index.get(self.root, 0)
        rot[root] = np.eye(3)
        pos[root] = 0.0
        for step in needed:
            parent_rot, parent_pos = rot[step.parent], pos[step.parent]
            flat = parent_rot.reshape(-1, 3)
            if step.origin_moves:
                pos[step.frame] = parent_pos + (flat @ step.origin[:3, 3]).reshape(b, 3)
            else:
                pos[step.frame] = parent_pos
            placed_rot = (flat @ step.origin[:3, :3]).reshape(b, 3, 3) if step.origin_turns else parent_rot
            if step.kind == "fixed":
                rot[step.frame] = placed_rot
                continue
            value = step.multiplier * q[:, step.variable] + step.offset
            if step.kind == "rotation":
                k = step.skew
                ak = (placed_rot.reshape(-1, 3) @ k).reshape(b, 3, 3)
                akk = (ak.reshape(-1, 3) @ k).reshape(b, 3, 3)
                out_rot = rot[step.frame]
                np.add(placed_rot, np.sin(value)[:, None, None] * ak, out=out_rot)
                np.multiply(akk, (1.0 - np.cos(value))[:, None, None], out=akk)
                out_rot += akk
            else:
                rot[step.frame] = placed_rot
                pos[step.frame] += value[:, None] * (placed_rot.reshape(-1, 3) @ step.axis).reshape(b, 3)
        out = np.empty((b, len(wanted), 4, 4))
        for column, frame in enumerate(wanted.tolist()):
            out[:, column, :3, :3] = rot[frame]
            out[:, column, :3, 3] = pos[frame]
        out[:, :, 3, :3] = 0.0
        out[:, :, 3, 3] = 1.0
        return out

    def _needed_steps(self, frames: tuple[int, ...]) -> tuple[_Step, ...]:
        """The steps placing ``frames`` and their ancestors, parents first."""
        cached = self._needed_cache.get(frames)
        if cached is None:
            need: set[int] = set()
            for f in frames:
                name = self._frames[f]
                while name in self._tree_joints and self._frame_index[name] not in need:
                    need.add(self._frame_index[name])
                    name = self._tree_joints[name].parent
            cached = self._needed_cache[frames] = tuple(s for s in self._steps if s.frame in need)
        return cached

    def joint_axes(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World position and unit direction of every variable joint's axis for ``q`` (b, n_joints):
        two arrays (b, n_joints, 3) [m] and [unit]. A variable outside the tree (a leader that only
        drives mimics) reports the axis of its first follower."""
        frames = self._frame_transforms(q)
        b = frames.shape[0]
        points = np.zeros((b, len(self.joints), 3))
        dirs = np.zeros((b, len(self.joints), 3))
        done: set[int] = set()
        # a variable's own joint first; a follower's axis only for leaders outside the tree
        for own in (True, False):
            for step in self._steps:
                if step.variable < 0 or step.variable in done:
                    continue
                joint = self._tree_joints[self._frames[step.frame]]
                if own != (joint.name in self._joint_index):
                    continue
                f = frames[:, step.frame]
                points[:, step.variable] = f[:, :3, 3]
                dirs[:, step.variable] = f[:, :3, :3] @ step.axis
                done.add(step.variable)
        return points, dirs

    def frame_tree(self) -> tuple[FramePlacement, ...]:
        """How every frame below the root is placed, parents first: what a viewer needs to pose
        the robot for any configuration (``frame = parent @ origin @ motion(value)``)."""
        out = []
        for child, step in self._step_of.items():
            variable = self.joints[step.variable].name if step.variable >= 0 else None
            out.append(
                FramePlacement(
                    frame=child,
                    parent=self._frames[step.parent],
                    joint=self._tree_joints[child],
                    motion=step.kind,
                    axis=step.axis,
                    variable=variable,
                    multiplier=step.multiplier,
                    offset=step.offset,
                )
            )
        return tuple(out)

    def parent_joint(self, link: str) -> Joint | None:
        """The joint that places ``link`` in the tree (``None`` for the root)."""
        return self._tree_joints.get(link)

    def root_path(self, link: str) -> tuple[Joint, ...]:
        """The tree joints from the root down to ``link``."""
        if link not in self._frame_index:
            raise UsageError.bad_choice("link", link, self.link_names)
        return tuple(self._tree_joints[f] for f in reversed(self._ancestors(link)[:-1]))

    def child_joints(self, link: str) -> tuple[Joint, ...]:
        """The tree joints whose parent is ``link``, in document order."""
        return tuple(j for j in self.robot.joints if j.parent == link and self._tree_joints.get(j.child) is j)

    def driver(self, joint: Joint) -> tuple[str, float] | None:
        """The variable moving a tree joint and its multiplier (1 for the variable's own joint,
        the folded mimic multiplier for a follower); ``None`` for joints that do not move."""
        if self._tree_joints.get(joint.child) is not joint:
            return None
        step = self._step_of[joint.child]
        if step.variable < 0:
            return None
        return self.joints[step.variable].name, step.multiplier

    def tree_axes(self, q: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """``{joint name: (world point (3,), unit direction (3,))}`` of every moving tree joint's
        axis at one configuration ``q`` (n_joints,)."""
        frames = self._frame_transforms(np.asarray(q, dtype=float)[None])[0]
        out = {}
        for child, step in self._step_of.items():
            if step.variable >= 0:
                frame = frames[step.frame]
                out[self._tree_joints[child].name] = (frame[:3, 3].copy(), frame[:3, :3] @ step.axis)
        return out

    def axis(self, joint: Joint, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World point on a tree joint's axis and its unit direction for configurations ``q``
        (b, n_joints): two arrays (b, 3)."""
        frame = self._frame_transforms(q)[:, self._frame_index[joint.child]]
        return frame[:, :3, 3], frame[:, :3, :3] @ _unit(joint.axis)

    def _ancestors(self, frame: str) -> list[str]:
        chain = [frame]
        while chain[-1] in self._tree_joints:
            chain.append(self._tree_joints[chain[-1]].parent)
        return chain

    def _variable_of(self, joint: Joint) -> str | None:
        if joint.name in self._joint_index:
            return joint.name
        if joint.name in self._leaders:
            leader = self._leaders[joint.name][0]
            return leader if leader in self._joint_index else None
        return None

    def path_joints(self, link_a: str, link_b: str) -> tuple[str, ...]:
        """Variables whose value changes the relative pose of two links: the variables of the
        joints on the tree path between them (a mimic joint contributes its leader), in
        configuration order."""
        key = (link_a, link_b) if link_a <= link_b else (link_b, link_a)
        found = self._path_memo.get(key)
        if found is None:
            found = self._path_memo[key] = self._path_joints(*key)
        return found

    def _path_joints(self, link_a: str, link_b: str) -> tuple[str, ...]:
        for name in (link_a, link_b):
            if name not in self._frame_index:
                raise UsageError.bad_choice("link", name, self.link_names)
        up_a, up_b = self._ancestors(link_a), self._ancestors(link_b)
        common = set(up_a) & set(up_b)
        names: set[str] = set()
        for chain in (up_a, up_b):
            for frame in chain:
                if frame in common:
                    break
                var = self._variable_of(self._tree_joints[frame])
                if var is not None:
                    names.add(var)
        return tuple(j.name for j in self.joints if j.name in names)

    def subtree(self, link: str) -> tuple[str, ...]:
        """Declared links at and below ``link``, in tree order."""
        if link not in self._frame_index:
            raise UsageError.bad_choice("link", link, self.link_names)
        below = {link}
        for frame in self._frames:  # tree order: a parent always comes before its children
            joint = self._tree_joints.get(frame)
            if joint is not None and joint.parent in below:
                below.add(frame)
        return tuple(n for n in self.link_names if n in below)
