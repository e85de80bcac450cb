"""Every threshold and tolerance of every rule, in one place, each with its unit.

Field names end in their unit (``_m``, ``_rad``, ``_kg``) or are dimensionless ratios and
fractions (stated in the comment). Configuration files override them by family and field
name (``[tool.geomcheck.thresholds.fit] protrusion_tolerance_m = 0.02``).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from geomcheck.errors import UsageError


@dataclass(frozen=True)
class LoadLimits:
    """Limits that protect the loader from hostile input."""

    max_file_bytes: int = 50 * 1024 * 1024  # one XML document [bytes]
    max_mesh_bytes: int = 200 * 1024 * 1024  # one mesh file [bytes]
    max_xml_depth: int = 256  # element nesting [levels]
    max_include_depth: int = 32  # nested xacro includes [levels]
    max_expanded_bytes: int = 64 * 1024 * 1024  # xacro output [bytes]
    max_macro_depth: int = 100  # nested macro calls [levels]
    max_macro_calls: int = 10_000  # macro expansions in one document (the PR2 makes 118) [count]
    max_xacro_elements: int = 25_000  # elements xacro evaluates, blocks inserted included (the 2009 PR2: 2917) [count]
    max_sibling_work: int = 4_000_000  # siblings passed over while xacro inserts nodes (the PR2: 1.03e6) [count]
    max_expression_work: int = 1_000_000  # range items and comprehension steps of all xacro expressions [count]
    max_model_files: int = 4_000  # files one MJCF model names: includes, sub-models, meshes, textures [count]
    # elements MuJoCo's parse of an MJCF model makes, <replicate>s repeated and <attach>ed models
    # counted (Menagerie's largest: 250); MuJoCo's compile grows with their square: 8000 replicated
    # bodies take 5 s [count]
    max_mjcf_elements: int = 10_000
    max_image_pixels: int = 64 * 1024 * 1024  # pixels of one texture or height field, read or generated [count]
    max_builtin_mesh_vertices: int = 1_000_000  # vertices of one MJCF builtin mesh (MuJoCo: 4 s a million) [count]
    # links, joints, frames and models of an SDFormat model once its includes are expanded (the
    # corpus's largest: 54) [count]
    max_sdf_elements: int = 10_000
    # magnitudes beyond which a URDF number is refused at load (GC126): geometry built from them is not finite
    max_length_m: float = 1e5  # origins, box sizes, radii, lengths, joint limits, axes [m]
    max_mesh_scale: float = 1e5  # mesh scale factors [ratio]
    max_mass_kg: float = 1e9  # link mass [kg]
    max_inertia_kg_m2: float = 1e12  # inertia tensor entries [kg m^2]
    # SDFormat's default joint limits, which Gazebo reads as "no limit": a revolute or prismatic
    # bound this large is that sentinel, not a slipped exponent [rad or m]
    unlimited_joint_bound: float = 1e16
    # nonzero sizes below which a primitive or a mesh scale is refused at load (GC126): tessellation,
    # SVDs and rasters of a body 1e-20 m across under- or overflow (1 nm is far below any robot part)
    min_size_m: float = 1e-9  # box sizes, cylinder radii and lengths, sphere radii [m]
    min_mesh_scale: float = 1e-9  # mesh scale factors [ratio]


@dataclass(frozen=True)
class StructureThresholds:
    min_axis_norm: float = 1e-9  # a joint axis shorter than this is zero [dimensionless]
    axis_norm_tolerance: float = 1e-3  # |norm - 1| above this: non-unit axis [dimensionless]
    # a mimic joint may fall short of its leader's image by this share of that range at the ends [fraction]
    mimic_range_tolerance: float = 0.01
    # ...or by no more than this at either end, in its own motion: the rounding of limits written to a few
    # decimals, which no linkage shows (Schunk SVH's finger spread, 0.0031 rad short) [rad]
    mimic_shortfall_rad: float = 0.0087
    mimic_shortfall_m: float = 0.0005  # the same for a prismatic mimic joint [m]
    # ...and cannot follow over this share of it or more: an error, not a warning [fraction]
    mimic_gross_share: float = 0.5


@dataclass(frozen=True)
class MeshThresholds:
    max_link_extent_m: float = 5.0  # a single link mesh larger than this is absurd [m]
    min_link_extent_m: float = 0.001  # smaller than this is absurd [m]
    unit_factor_tolerance: float = 0.25  # |log(ratio / factor)| within log(1+this) [ratio]
    # shared edges run the same way by both faces, at or above this share: mixed winding (GC210) [fraction]
    inconsistent_winding_share: float = 0.25
    # meshes with more triangles than this are not examined for winding (bounded work) [count]
    winding_max_faces: int = 2_000_000


@dataclass(frozen=True)
class FitThresholds:
    protrusion_tolerance_m: float = 0.010  # mesh may stick out of its primitive this far [m]
    # ...or less on small parts: this share of the mesh's smallest extent (its bounding box's
    # shortest side in the link frame), and for each collision element of the smallest extent
    # of the part of the mesh it answers for, when smaller; never below protrusion_floor_m
    protrusion_tolerance_fraction: float = 0.25  # [fraction of a length]
    protrusion_floor_m: float = 0.002  # the size-relative tolerance is at least this [m]
    # ...and on large parts this share of the mesh's largest extent when larger, up to
    # protrusion_size_cap_m: a primitive standing for a 0.5 m body cannot follow its detail to 10 mm
    protrusion_size_fraction: float = 0.05  # [fraction of a length]
    protrusion_size_cap_m: float = 0.025  # [m]
    # a box on a link ending a chain whose thinnest side is under this share of the next, on the
    # mesh's face, is a contact plate (a sole) [ratio]
    contact_plate_ratio: float = 0.1
    # positions of a joint over its range at which a part without collision must stay inside the
    # body it hangs from (twice as many over a full turn) [count]
    joint_samples: int = 9
    min_coverage: float = 0.90  # share of mesh surface inside the primitive [fraction]
    max_slack: float = 4.0  # primitive volume / mesh convex hull volume [ratio]
    offset_overlap_fraction: float = 0.05  # below this share of mesh inside: disjoint/offset [fraction]
    axis_coverage_gain: float = 0.30  # another cylinder axis must cover this much more [fraction]
    surface_samples: int = 2000  # area-weighted samples per mesh [count]
    seed: int = 0  # sampling seed
    gross_coverage: float = 0.50  # a primitive covering less than this is an error, not a warning [fraction]
    offset_min_fraction: float = 0.20  # centring shift / primitive's largest extent that makes it misplaced [ratio]
    min_slack_gain: float = 1.5  # oversized only if the suggested primitive's slack is this many times smaller [ratio]
    # over-coverage (GC302): a side of an element standing off its part of the mesh by more than the
    # part's tolerance and this share of the part's extent across it...
    oversize_gap_fraction: float = 0.10  # [fraction of a length]
    # ...and more than this: a shape a few millimetres proud of its part is padding, within the margin the
    # sweeps call a near miss (self_collision.clearance_margin_m), not a false contact [m]
    oversize_floor_m: float = 0.005
    # ...while a primitive of its kind fitted to the part has this many times less volume [ratio]
    oversize_volume_ratio: float = 1.5
    # a link's only element whose volume is this many times that of another kind fitted to the mesh [ratio]
    oversize_kind_ratio: float = 2.0
    # an element of a union away from the mesh but against it, and at most this share of the mesh's
    # hull volume, stands for what the visual does not draw (GC303 info) [fraction]
    beside_volume_share: float = 0.10
    # an element of a union answering for less than this share of the link's mesh is not judged [fraction]
    oversize_min_part_share: float = 0.25
    simple_fit_margin: float = 0.10  # a simpler suggested frame may be this much larger in volume [fraction]
    mesh_overshoot_tolerance_m: float = 0.020  # a collision mesh may reach this far out of the visual hull [m]
    # ...and one reaching this share of the visual's largest extent out of it is another shape or place [fraction]
    mesh_gross_overshoot_fraction: float = 0.25
    volume_samples: int = 512  # points per collision element for its overlap with the visual hull [count]
    placeholder_extent_m: float = 0.002  # visual geometry no larger than this is a placeholder, not fitted [m]
    # collision elements all no larger than this stand for no part (a marker, a simulator's stand-in): a link
    # whose mesh another link's collision holds needs nothing of them (GC301, GC303) [m]
    marker_element_m: float = 0.01
    # a sphere this close to an end of a cylinder's axis, with its radius this close to the
    # cylinder's, closes a capsule of the link (a cylinder and two such spheres) [m]
    capsule_cap_tolerance_m: float = 0.001


@dataclass(frozen=True)
class SelfCollisionThresholds:
    clearance_margin_m: float = 0.005  # sweep clearance below this is a warning [m]
    contact_tolerance_m: float = 1e-4  # distance at or below this counts as contact [m]
    always_fraction: float = 0.95  # in collision in at least this share of samples: Always [fraction]
    witness_distance_m: float = 0.05  # Never pairs closer than this get a witness search [m]
    samples: int = 10000  # random configurations for the matrix [count]
    seed: int = 0  # sampling seed
    sweep_grid_points: int = 360  # first grid of the continuous-joint sweep [points per turn]
    # of that grid, the cells first asked exactly when one joint turns a mesh past a still link: the
    # turn bound then proves the others at the clearance they give, without a query [points per turn]
    sweep_screen_points: int = 24
    sweep_clearance_resolution_m: float = 1e-4  # the sweep's smallest clearance is proven to within this [m]
    sweep_angle_resolution_rad: float = 1e-3  # ends of colliding angle ranges are located to this [rad]
    sweep_max_queries: int = 20000  # distance queries per link pair and sweep before giving up [count]
    # distance queries of all the sweeps of one check, a query between meshes counting as
    # sweep_mesh_query_weight (about what it costs against primitives': 0.4 ms and 10 us): a
    # robot whose legs are continuous joints (PyBullet's mini cheetah: 12 of them, 34 mesh pairs
    # a sweep) shares it out [count]
    sweep_max_queries_total: int = 1000000
    sweep_mesh_query_weight: int = 10  # [count]
    # a pair in collision at the default pose is collided again in this many poses of the joints
    # between its links: in nearly all of them (always_fraction) it is a designed overlap [count]
    default_pose_samples: int = 100
    # meshes in contact at the default pose that part after a shift this small graze (facets touching) [m]
    mesh_graze_m: float = 0.0015
    # a pair in collision at the default pose with joints between them at a limit is collided again
    # with those joints moved this share of their range off it: parted, the contact is at the stop [fraction]
    stop_probe_fraction: float = 0.05
    # one link drawn with at least this share of its visual surface within the other's convex hull
    # is nested in it (a telescope's inner section) [fraction]
    nested_share: float = 0.5


@dataclass(frozen=True)
class MotionThresholds:
    """How joints move their parts (GC42x)."""

    # a part is round about an axis when its reach from it differs by at most this share around it [fraction]
    revolution_roundness: float = 0.05
    # ...two principal moments of its surface within this share of each other, the third apart [fraction]
    revolution_equal_moments: float = 0.10
    # ...and no longer along that axis than this many times across it (a wheel, a flange) [ratio]
    revolution_max_length_ratio: float = 1.0
    # the joint axis passes through the part: within this share of its radius of its centre [fraction]
    revolution_centre_fraction: float = 0.25
    # a joint axis further than this from the part's own axis turns it off its axis [deg]
    revolution_axis_tolerance_deg: float = 10.0
    # a part's axis measured this close to an axis of the joint's frame is that axis [deg]
    revolution_snap_deg: float = 2.0


@dataclass(frozen=True)
class InertiaThresholds:
    relative_tolerance: float = 0.01  # slack on triangle inequality and geometry bounds [fraction]
    min_mass_kg: float = 0.0  # masses at or below this are invalid [kg]
    com_margin_m: float = 0.001  # centre of mass may lie this far outside the geometry's hull [m]
    copied_inertia_mass_ratio: float = 2.0  # identical tensors with masses this far apart: copied [ratio]
    # one tensor copied onto parts of other masses by this many <inertial> elements or more: typed for
    # every part rather than copied from one; one finding for all of them [count]
    shared_tensor_sources: int = 3
    max_density_kg_m3: float = 22600.0  # osmium, the densest element: mass / hull volume above is impossible [kg/m^3]
    # severity follows consequence, never below warning for the description's own values: a
    # plausibility finding (GC505-GC508) that is an error is a warning on a link carrying less than
    # this share of the robot's mass, and says so (fixed-joint merging likewise, judged on the
    # merged body itself, without a threshold)
    minor_mass_share: float = 0.01  # [fraction]
    # a link whose geometry spans no more than this is a frame's marker, not a part: its
    # inertial cannot be judged against it (the fit family's placeholder_extent_m)
    placeholder_extent_m: float = 0.002  # [m]
    # ...and one drawn with primitives alone no larger than this: the marker box of a frame [m]
    marker_extent_m: float = 0.01
    # a light link's tensor beyond the geometry's bound by at most this factor in moment: a little off (info) [ratio]
    marginal_ratio: float = 2.0
    # a mass at or below this is what authors type for a massless frame where a simulator refuses
    # zero (no robot part weighs 0.1 g): its plausibility findings are info [kg]
    negligible_mass_kg: float = 1e-4
    # left and right counterparts (GC510): frames mirrored across the xz plane within this [m]...
    counterpart_origin_tolerance_m: float = 0.005
    # ...geometry in mirror-image boxes within this share of its size [fraction]...
    counterpart_geometry_fraction: float = 0.05
    # ...and then masses within this share of the larger [fraction]...
    counterpart_mass_fraction: float = 0.10
    # ...centres of mass, one mirrored, within this distance [m] or this share of the part's size [fraction]...
    counterpart_com_m: float = 0.005
    counterpart_com_fraction: float = 0.10
    # ...and tensors per unit mass within this share of their largest value [fraction]
    counterpart_tensor_fraction: float = 0.25
    # a centre of mass written 0 0 0 with the part's centroid this share of its extent away (GC511) [fraction]
    com_origin_fraction: float = 1.0 / 3.0
    # ...or this share away and this many times nearer with two coordinates exchanged [fraction], [ratio]
    com_swap_fraction: float = 0.2
    com_swap_gain: float = 3.0
    # this many links or more left at the origin are one unfilled template: one finding naming them [count]
    com_template_links: int = 3


@dataclass(frozen=True)
class AnalysisThresholds:
    """How exactly large meshes are analysed: the bounds that keep time and memory flat as
    meshes grow. Not rules' tolerances; the report states the precision they give."""

    hull_exact_points: int = 20000  # convex hulls of up to this many distinct vertices are exact [count]
    # larger point sets: no vertex further above the hull's facets than this share of the bounding-box diagonal
    hull_tolerance_fraction: float = 5e-4  # [fraction]
    chunk_elements: int = 4_000_000  # points x planes (or directions) evaluated per numpy block [count]
    raster_chunk_triangles: int = 65_536  # triangles rasterised per block for the views [count]


@dataclass(frozen=True)
class ViewThresholds:
    """Precision of the report's pictures (the ``views`` and ``scene`` sections), not of any rule."""

    raster_pixels: int = 160  # silhouette raster cells across the link's largest extent [count]
    simplify_tolerance: float = 0.004  # Douglas-Peucker tolerance [fraction of the link's largest extent]
    coordinate_step_m: float = 0.0001  # outline coordinates rounded to this [m]
    circle_segments: int = 48  # outline of a cylinder or sphere [segments per turn]
    scene_triangles: int = 150_000  # the 3D view's meshes together; more are decimated for display [triangles]
    scene_mesh_triangles: int = 300  # the fewest triangles decimation leaves a mesh [triangles]


@dataclass(frozen=True)
class DiffThresholds:
    metric_relative_tolerance: float = 0.01  # worsening of a kept finding's metric that counts as regression [fraction]


@dataclass(frozen=True)
class Thresholds:
    limits: LoadLimits = field(default_factory=LoadLimits)
    structure: StructureThresholds = field(default_factory=StructureThresholds)
    meshes: MeshThresholds = field(default_factory=MeshThresholds)
    fit: FitThresholds = field(default_factory=FitThresholds)
    self_collision: SelfCollisionThresholds = field(default_factory=SelfCollisionThresholds)
    motion: MotionThresholds = field(default_factory=MotionThresholds)
    inertia: InertiaThresholds = field(default_factory=InertiaThresholds)
    diff: DiffThresholds = field(default_factory=DiffThresholds)
    views: ViewThresholds = field(default_factory=ViewThresholds)
    analysis: AnalysisThresholds = field(default_factory=AnalysisThresholds)

    def with_overrides(self, overrides: Mapping[str, Mapping[str, Any]]) -> Thresholds:
        """A copy with ``{family: {field: value}}`` applied; unknown names are a :class:`UsageError`."""
        families = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        for family, values in overrides.items():
            if family not in families:
                raise UsageError.bad_choice("threshold family", family, sorted(families))
            current = families[family]
            names = {f.name: f for f in dataclasses.fields(current)}
            converted: dict[str, int | float] = {}
            for key, value in values.items():
                if key not in names:
                    raise UsageError.bad_choice(f"threshold in {family}", key, sorted(names))
                default = getattr(current, key)
                if isinstance(value, bool) or not isinstance(value, int | float):
                    raise UsageError(f"threshold {family}.{key} must be a number, got {value!r}")
                if isinstance(default, int) and not isinstance(default, bool):
                    if int(value) != value:
                        raise UsageError(f"threshold {family}.{key} must be an integer, got {value!r}")
                    converted[key] = int(value)
                else:
                    converted[key] = float(value)
            families[family] = dataclasses.replace(current, **converted)
        return Thresholds(**families)
