"""libsdformat's own tests (gazebosim/sdformat) of files holding one model, one case per file
or inline string, transcribed.

Verdicts come from the tests that load the file: ``TEST(check, SDF)`` and its neighbours in
``src/gz_TEST.cc``, which run ``gz sdf --check`` on a file and expect ``Valid.`` or an error
message, and the DOM tests of ``test/integration/*.cc`` (``root.Load(file)`` with no error, or
the errors it lists). The file is ``test/sdf/NAME`` written out again without its comments; a
case that both kinds of test read cites the DOM test, whose assertions are the facts. Facts
are what geomcheck's report shows: names, counts (SDFormat's links and joints, those of nested
models included), shapes, inertials, joint types, parents and children (the links a frame
resolves to), limits, axes (resolved in the child link's frame) and the pose of one link in
another joined to it. Files holding a world, several models or an include of a model
directory are not single-model cases and are left out; so are assertions on what geomcheck
does not model (sensors, plugins, frames other than links, a revolute joint's unused second
axis, damping and springs). Sources and licences: NOTICE.md.
"""

# ruff: noqa: E501 (the descriptions are the reference tests' XML, one element per line as they wrote it)

from __future__ import annotations

import math

from tests.load.conformance.harness import Case, Fact, fact

GZ_TEST = "src/gz_TEST.cc"
MODEL_DOM, JOINT_DOM, LINK_DOM = (
    "test/integration/model_dom.cc",
    "test/integration/joint_dom.cc",
    "test/integration/link_dom.cc",
)
AXIS_DOM, GEOMETRY_DOM, ROOT_DOM = (
    "test/integration/joint_axis_dom.cc",
    "test/integration/geometry_dom.cc",
    "test/integration/root_dom.cc",
)
F = fact
HALF_PI = math.pi / 2


def sdf(body: str, version: str = "1.7") -> str:
    return f'<?xml version="1.0" ?>\n<sdf version="{version}">\n{body}\n</sdf>\n'


def case(
    source: str,
    test: str,
    verdict: str,
    text: str,
    asset: str | None,
    *,
    problem: str = "",
    facts: tuple[Fact, ...] = (),
) -> Case:
    return Case(source, test, verdict, text, asset=asset, problem=problem, facts=facts, filename="model.sdf")  # type: ignore[arg-type]


def check(test_file: str, verdict: str, text: str, problem: str = "", facts: tuple[Fact, ...] = ()) -> Case:
    """A case of ``TEST(check, SDF)``: ``gz sdf -k test/sdf/<test_file>``."""
    return case(GZ_TEST, "check.SDF", verdict, text, test_file, problem=problem, facts=facts)


def relative(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, ...]:
    """The pose of frame ``b`` in frame ``a``, both given in one frame (x y z roll pitch yaw)."""
    import numpy as np

    from geomcheck.model import Pose, rpy_from_matrix

    m = np.linalg.inv(Pose(a[:3], a[3:]).matrix()) @ Pose(b[:3], b[3:]).matrix()  # type: ignore[arg-type]
    return (*(float(v) for v in m[:3, 3]), *rpy_from_matrix(m[:3, :3]))


DOUBLE_PENDULUM = sdf(
    """<model name="double_pendulum_with_base">
  <link name="base">
    <inertial><mass>100</mass></inertial>
    <visual name="vis_plate_on_ground">
      <pose>0 0 0.01 0 0 0</pose>
      <geometry><cylinder><radius>0.8</radius><length>0.02</length></cylinder></geometry>
    </visual>
    <visual name="vis_pole">
      <pose>-0.275 0 1.1 0 0 0</pose>
      <geometry><box><size>0.2 0.2 2.2</size></box></geometry>
    </visual>
    <collision name="col_plate_on_ground">
      <pose>0 0 0.01 0 0 0</pose>
      <geometry><cylinder><radius>0.8</radius><length>0.02</length></cylinder></geometry>
    </collision>
    <collision name="col_pole">
      <pose>-0.275 0 1.1 0 0 0</pose>
      <geometry><box><size>0.2 0.2 2.2</size></box></geometry>
    </collision>
  </link>
  <link name="upper_link">
    <pose>0 0 2.1 -1.5708 0 0</pose>
    <self_collide>0</self_collide>
    <inertial><pose>0 0 0.5 0 0 0</pose></inertial>
    <visual name="vis_upper_joint">
      <pose>-0.05 0 0 0 1.5708 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.3</length></cylinder></geometry>
    </visual>
    <visual name="vis_lower_joint">
      <pose>0 0 1.0 0 1.5708 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.2</length></cylinder></geometry>
    </visual>
    <visual name="vis_cylinder">
      <pose>0 0 0.5 0 0 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.9</length></cylinder></geometry>
    </visual>
    <collision name="col_upper_joint">
      <pose>-0.05 0 0 0 1.5708 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.3</length></cylinder></geometry>
    </collision>
    <collision name="col_lower_joint">
      <pose>0 0 1.0 0 1.5708 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.2</length></cylinder></geometry>
    </collision>
    <collision name="col_cylinder">
      <pose>0 0 0.5 0 0 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.9</length></cylinder></geometry>
    </collision>
  </link>
  <link name="lower_link">
    <pose>0.25 1.0 2.1 -2 0 0</pose>
    <self_collide>0</self_collide>
    <inertial><pose>0 0 0.5 0 0 0</pose></inertial>
    <visual name="vis_lower_joint">
      <pose>0 0 0 0 1.5708 0</pose>
      <geometry><cylinder><radius>0.08</radius><length>0.3</length></cylinder></geometry>
    </visual>
    <visual name="vis_cylinder">
      <pose>0 0 0.5 0 0 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.9</length></cylinder></geometry>
    </visual>
    <collision name="col_lower_joint">
      <pose>0 0 0 0 1.5708 0</pose>
      <geometry><cylinder><radius>0.08</radius><length>0.3</length></cylinder></geometry>
    </collision>
    <collision name="col_cylinder">
      <pose>0 0 0.5 0 0 0</pose>
      <geometry><cylinder><radius>0.1</radius><length>0.9</length></cylinder></geometry>
    </collision>
  </link>
  <joint name="upper_joint" type="revolute">
    <parent>base</parent>
    <child>upper_link</child>
    <axis><xyz>1.0 0 0</xyz></axis>
  </joint>
  <joint name="lower_joint" type="revolute">
    <parent>upper_link</parent>
    <child>lower_link</child>
    <axis><xyz>1.0 0 0</xyz></axis>
  </joint>
</model>""",
    "1.6",
)

JOINT_COMPLETE = sdf(
    """<model name="test">
  <link name="link1"/><link name="link2"/><link name="link3"/><link name="link4"/><link name="link5"/>
  <link name="link6"/><link name="link7"/><link name="link8"/><link name="link9"/><link name="link10"/>
  <joint name="revolute_joint" type="revolute">
    <pose>1 0 0 0 0 0</pose>
    <child>link1</child>
    <parent>link2</parent>
    <axis>
      <xyz>0 0 1</xyz>
      <use_parent_model_frame>true</use_parent_model_frame>
      <limit><lower>-0.5</lower><upper>0.5</upper><effort>123.4</effort><velocity>12</velocity></limit>
      <dynamics><damping>0.1</damping><friction>0.2</friction><spring_reference>1.3</spring_reference>
        <spring_stiffness>10.6</spring_stiffness></dynamics>
    </axis>
    <axis2>
      <xyz>0 1 0</xyz>
      <use_parent_model_frame>false</use_parent_model_frame>
      <limit><lower>-1</lower><upper>1</upper><effort>0.5</effort><velocity>200</velocity></limit>
    </axis2>
    <physics><ode><cfm_damping>1</cfm_damping><limit><cfm>0</cfm><erp>0.2</erp></limit></ode></physics>
  </joint>
  <joint name="ball_joint" type="ball"><pose>0 1 0 0 0 0</pose><child>link2</child><parent>link3</parent></joint>
  <joint name="continuous_joint" type="continuous">
    <pose>0 0 1 0 0 0</pose><child>link3</child><parent>link4</parent><axis><xyz>0 0 1</xyz></axis>
  </joint>
  <joint name="fixed_joint" type="fixed"><pose>0 0 0 1 0 0</pose><child>link4</child><parent>link5</parent></joint>
  <joint name="gearbox_joint" type="gearbox">
    <pose>0 0 0 0 1 0</pose><child>link5</child><parent>link6</parent><axis><xyz>0 0 1</xyz></axis>
  </joint>
  <joint name="prismatic_joint" type="prismatic">
    <pose>0 0 0 0 0 1</pose><child>link6</child><parent>link7</parent><axis><xyz>0 0 1</xyz></axis>
  </joint>
  <joint name="revolute2_joint" type="revolute2">
    <pose>2 0 0 0 0 0</pose><child>link7</child><parent>link8</parent><axis><xyz>0 0 1</xyz></axis>
  </joint>
  <joint name="screw_joint" type="screw">
    <pose>0 2 0 0 0 0</pose><child>link8</child><parent>link9</parent><thread_pitch>20</thread_pitch>
    <axis><xyz>0 0 1</xyz></axis>
  </joint>
  <joint name="universal_joint" type="universal">
    <pose>0 0 2 0 0 0</pose><child>link9</child><parent>link10</parent><axis><xyz>0 0 1</xyz></axis>
  </joint>
</model>""",
    "1.6",
)

SHAPES = sdf(
    """<model name="shapes">
  <link name="link">
    <collision name="box_col"><geometry><box><size>3 4 5</size></box></geometry></collision>
    <visual name="box_vis"><geometry><box><size>1 2 3</size></box></geometry></visual>
    <collision name="capsule_col"><geometry><capsule><radius>0.2</radius><length>0.1</length></capsule></geometry></collision>
    <visual name="capsule_vis"><geometry><capsule><radius>2.1</radius><length>10.2</length></capsule></geometry></visual>
    <collision name="cone_col"><geometry><cone><radius>0.2</radius><length>0.1</length></cone></geometry></collision>
    <visual name="cone_vis"><geometry><cone><radius>2.1</radius><length>10.2</length></cone></geometry></visual>
    <collision name="cylinder_col"><geometry><cylinder><radius>0.2</radius><length>0.1</length></cylinder></geometry></collision>
    <visual name="cylinder_vis"><geometry><cylinder><radius>2.1</radius><length>10.2</length></cylinder></geometry></visual>
    <collision name="ellipsoid_col"><geometry><ellipsoid><radii>1.0 2.0 3.0</radii></ellipsoid></geometry></collision>
    <visual name="ellipsoid_vis"><geometry><ellipsoid><radii>0.1 0.2 0.3</radii></ellipsoid></geometry></visual>
    <collision name="plane_col"><geometry><plane><normal>1 0 0</normal><size>1.4 6.3</size></plane></geometry></collision>
    <visual name="plane_vis"><geometry><plane><normal>0 1 0</normal><size>2 4</size></plane></geometry></visual>
    <collision name="sphere_col"><geometry><sphere><radius>23.4</radius></sphere></geometry></collision>
    <visual name="sphere_vis"><geometry><sphere><radius>100.2</radius></sphere></geometry></visual>
    <collision name="mesh_col">
      <geometry><mesh optimization="convex_decomposition">
        <convex_decomposition><max_convex_hulls>4</max_convex_hulls><voxel_resolution>400000</voxel_resolution>
        </convex_decomposition>
        <uri>https://fuel.gazebosim.org/1.0/an_org/models/a_model/mesh/mesh.dae</uri>
        <submesh><name>my_submesh</name><center>true</center></submesh>
        <scale>0.1 0.2 0.3</scale>
      </mesh></geometry>
    </collision>
    <visual name="mesh_vis">
      <geometry><mesh>
        <uri>https://fuel.gazebosim.org/1.0/an_org/models/a_model/mesh/mesh.dae</uri>
        <submesh><name>another_submesh</name><center>false</center></submesh>
        <scale>1.2 2.3 3.4</scale>
      </mesh></geometry>
    </visual>
    <collision name="heightmap_col">
      <geometry><heightmap>
        <uri>https://fuel.gazebosim.org/1.0/an_org/models/a_model/materials/textures/heightmap.png</uri>
        <size>500 500 100</size><pos>1 2 3</pos>
      </heightmap></geometry>
    </collision>
    <collision name="polyline_col">
      <geometry>
        <polyline><point>-0.5 -0.5</point><point>-0.5 0.5</point><point>0.5 0.5</point><point>0.5 -0.5</point>
          <point>-0.5 -0.5</point><height>0.5</height></polyline>
        <polyline><point>-0.3 -0.3</point><point>-0.3 0.3</point><point>0.3 0.3</point><point>0.3 -0.3</point>
          <height>0.3</height></polyline>
      </geometry>
    </collision>
    <visual name="polyline_vis">
      <geometry><polyline><point>-0.2 -0.2</point><point>-0.2 0.2</point><point>0.2 0.2</point><height>1.0</height>
      </polyline></geometry>
    </visual>
  </link>
</model>""",
    "1.11",
)

MIMIC_HEADER = """<model name="test">
  <link name="link1"/>
  <link name="link2"/>
  <link name="link3"/>"""

# joint_nested_parent_child.sdf: link poses in the model frame, and the nested models' frames
M1_L1, M1_L2, TOP_L1 = (0, 0, 1, 0, 0, 0), (1, 1, 0, 0, 0, 0), (0, 0, 10, 0, HALF_PI, 0)
M2_L1 = (0, 0, 1, HALF_PI, 0, 0)  # M1::M2::L1 is at M1::M2's frame

CASES: tuple[Case, ...] = (
    # src/gz_TEST.cc, TEST(check, SDF): valid files
    check(
        "model_duplicate_plugins.sdf",
        "load",
        sdf("""<model name="model_duplicate_plugins">
  <link name="link1">
    <sensor name="test_sensor" type="imu">
      <plugin name="sensor_dup_name" filename="test/file/name"/>
      <plugin name="sensor_dup_name" filename="test/file/name"/>
    </sensor>
  </link>
  <plugin name="dup_name" filename="test/file/name"/>
  <plugin name="dup_name" filename="test/file/name"/>
</model>"""),
        facts=(F("count links", 1),),
    ),
    check(
        "link_duplicate_cousin_collisions.sdf",
        "load",
        sdf(
            """<model name="link_collision_cousins_same_name">
  <link name="link1"><pose>1 0 0 0 0 0</pose><collision name="collision"><pose>0 1 0 0 0 0</pose></collision></link>
  <link name="link2"><pose>2 0 0 0 0 0</pose><collision name="collision"><pose>0 2 0 0 0 0</pose></collision></link>
</model>""",
            "1.6",
        ),
        facts=(F("count links", 2), F("link link1", True), F("link link2", True)),
    ),
    check(
        "link_duplicate_cousin_visuals.sdf",
        "load",
        sdf(
            """<model name="duplicate_cousin_visuals">
  <link name="link1"><pose>1 0 0 0 0 0</pose><visual name="visual"><pose>0 1 0 0 0 0</pose></visual></link>
  <link name="link2"><pose>2 0 0 0 0 0</pose><visual name="visual"><pose>0 2 0 0 0 0</pose></visual></link>
</model>""",
            "1.6",
        ),
        facts=(F("count links", 2),),
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadJointParentWorld",
        "load",
        sdf(
            """<model name="joint_parent_world">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <joint name="joint" type="fixed">
    <pose>0 0 3 0 0 0</pose>
    <parent>world</parent>
    <child>link</child>
  </joint>
</model>""",
            "1.6",
        ),
        "joint_parent_world.sdf",
        facts=(
            F("name", "joint_parent_world"),
            F("count links", 1),
            F("count joints", 1),
            F("joint joint child", "link"),
            F("joint joint parent", "world"),
        ),
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadJointChildFrame",
        "load",
        sdf(
            """<model name="joint_child_frame">
  <link name="parent_link"><pose>0 0 1 0 0 0</pose></link>
  <link name="child_link"><pose>0 0 10 0 0 0</pose></link>
  <frame name="child_frame" attached_to="child_link"><pose>1 0 0 0 0 0</pose></frame>
  <joint name="joint" type="fixed">
    <pose>0 1 0 0 0 0</pose>
    <parent>parent_link</parent>
    <child>child_frame</child>
  </joint>
</model>""",
            "1.8",
        ),
        "joint_child_frame.sdf",
        facts=(
            F("count links", 2),
            F("count joints", 1),
            F("joint joint child", "child_link"),
            F("joint joint parent", "parent_link"),
            F("pose parent_link child_link", (0, 0, 9, 0, 0, 0)),
        ),
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadJointParentFrame",
        "load",
        sdf(
            """<model name="joint_parent_frame">
  <link name="parent_link"><pose>0 0 1 0 0 0</pose></link>
  <link name="child_link"><pose>0 0 10 0 0 0</pose></link>
  <frame name="parent_frame" attached_to="parent_link"><pose>1 0 0 0 0 0</pose></frame>
  <joint name="joint" type="fixed">
    <pose>0 1 0 0 0 0</pose>
    <parent>parent_frame</parent>
    <child>child_link</child>
  </joint>
</model>""",
            "1.8",
        ),
        "joint_parent_frame.sdf",
        facts=(
            F("count links", 2),
            F("count joints", 1),
            F("joint joint child", "child_link"),
            F("joint joint parent", "parent_link"),
            F("pose parent_link child_link", (0, 0, 9, 0, 0, 0)),
        ),
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.InfiniteLimits",
        "load",
        sdf(
            """<model name="joint_axis_infinite_limits">
  <link name="link1"/><link name="link2"/><link name="link3"/><link name="link4"/><link name="link5"/><link name="link6"/>
  <joint name="default_joint_limits" type="revolute">
    <child>link1</child><parent>link2</parent><axis><xyz>1 0 0</xyz></axis>
  </joint>
  <joint name="finite_joint_limits" type="revolute">
    <child>link3</child><parent>link4</parent>
    <axis><xyz>1 0 0</xyz><limit><lower>-1.5</lower><upper>1.5</upper><velocity>2.5</velocity><effort>5.5</effort></limit></axis>
  </joint>
  <joint name="infinite_joint_limits_inf" type="revolute">
    <child>link4</child><parent>link5</parent>
    <axis><xyz>1 0 0</xyz><limit><lower>-inf</lower><upper>inf</upper><velocity>inf</velocity><effort>inf</effort></limit></axis>
  </joint>
  <joint name="infinite_joint_limits_neg" type="revolute">
    <child>link5</child><parent>link6</parent>
    <axis><xyz>1 0 0</xyz><limit><lower>-inf</lower><upper>inf</upper><velocity>-1</velocity><effort>-1</effort></limit></axis>
  </joint>
</model>""",
            "1.6",
        ),
        "joint_axis_infinite_limits.sdf",
        facts=(
            F("name", "joint_axis_infinite_limits"),
            F("joint default_joint_limits limit.lower", -math.inf),
            F("joint default_joint_limits limit.upper", math.inf),
            F("joint default_joint_limits limit.effort", math.inf),
            F("joint default_joint_limits limit.velocity", math.inf),
            F("joint finite_joint_limits limit.lower", -1.5),
            F("joint finite_joint_limits limit.upper", 1.5),
            F("joint finite_joint_limits limit.velocity", 2.5),
            F("joint finite_joint_limits limit.effort", 5.5),
            F("joint infinite_joint_limits_inf limit.lower", -math.inf),
            F("joint infinite_joint_limits_inf limit.upper", math.inf),
            F("joint infinite_joint_limits_inf limit.effort", math.inf),
            F("joint infinite_joint_limits_inf limit.velocity", math.inf),
            F("joint infinite_joint_limits_neg limit.lower", -math.inf),
            F("joint infinite_joint_limits_neg limit.upper", math.inf),
            F("joint infinite_joint_limits_neg limit.effort", math.inf),
            F("joint infinite_joint_limits_neg limit.velocity", math.inf),
        ),
    ),
    case(
        MODEL_DOM,
        "DOMRoot.LoadCanonicalLink",
        "load",
        sdf("""<model name="model_canonical_link" canonical_link="link2">
  <link name="link1"><pose>1 0 0 0 0 0</pose></link>
  <link name="link2"><pose>0 2 0 0 0 0</pose></link>
</model>"""),
        "model_canonical_link.sdf",
        facts=(
            F("name", "model_canonical_link"),
            F("count links", 2),
            F("count joints", 0),
            F("link link1", True),
            F("link link2", True),
        ),
    ),
    case(
        MODEL_DOM,
        "DOMRoot.NestedModel",
        "load",
        sdf(
            """<model name='top_level_model'>
  <link name='parent'/>
  <link name='child'/>
  <model name='nested_model'><link name='nested_link01'/></model>
  <joint name='top_level_joint' type='revolute'>
    <parent>parent</parent>
    <child>child</child>
    <axis><xyz>1 0 0</xyz></axis>
  </joint>
</model>""",
            "1.6",
        ),
        "nested_model.sdf",
        facts=(
            F("name", "top_level_model"),
            F("link parent", True),
            F("link child", True),
            F("link nested_model::nested_link01", True),
            F("count joints", 1),
            F("joint top_level_joint parent", "parent"),
            F("joint top_level_joint child", "child"),
        ),
    ),
    case(
        MODEL_DOM,
        "DOMRoot.LoadNestedCanonicalLink",
        "load",
        sdf("""<model name="top">
  <frame name="F"/>
  <model name="nested" canonical_link="link2"><link name="link1"/><link name="link2"/></model>
  <model name="shallow">
    <frame name="F"/>
    <model name="deep"><model name="deeper"><model name="deepest"><link name="deepest_link"/></model></model></model>
  </model>
</model>"""),
        "nested_canonical_link.sdf",
        facts=(
            F("name", "top"),
            F("count joints", 0),
            F("link nested::link1", True),
            F("link nested::link2", True),
            F("link shallow::deep::deeper::deepest::deepest_link", True),
        ),
    ),
    case(
        MODEL_DOM,
        "DOMRoot.LoadNestedExplicitCanonicalLink",
        "load",
        sdf(
            """<model name="top" canonical_link="nested::link2">
  <frame name="F"/>
  <model name="nested"><link name="link1"/><link name="link2"/></model>
</model>""",
            "1.8",
        ),
        "nested_explicit_canonical_link.sdf",
        facts=(F("name", "top"), F("count joints", 0), F("link nested::link2", True)),
    ),
    check(
        "model_frame_attached_to.sdf",
        "load",
        sdf("""<model name="model_frame_attached_to">
  <link name="L"/>
  <frame name="F00"/>
  <frame name="F0" attached_to=""/>
  <frame name="F000" attached_to="__model__"/>
  <frame name="F1" attached_to="L"/>
  <frame name="F2" attached_to="F1"/>
</model>"""),
        facts=(F("count links", 1),),
    ),
    check(
        "model_frame_attached_to_joint.sdf",
        "load",
        sdf("""<model name="model_frame_attached_to_joint">
  <link name="P"/>
  <link name="C"/>
  <joint name="J" type="fixed"><parent>P</parent><child>C</child></joint>
  <frame name="F1" attached_to="P"/>
  <frame name="F2" attached_to="C"/>
  <frame name="F3" attached_to="J"/>
  <frame name="F4" attached_to="F3"/>
</model>"""),
        facts=(F("count links", 2), F("count joints", 1)),
    ),
    check(
        "model_frame_attached_to_nested_model.sdf",
        "load",
        sdf("""<model name="model_frame_attached_to_nested_model">
  <link name="link"/>
  <model name="nested_model"><link name="nested_link"/></model>
  <frame name="F1" attached_to="nested_model"/>
  <frame name="F2" attached_to="F1"/>
</model>"""),
        facts=(F("count links", 2),),
    ),
    check(
        "model_link_relative_to.sdf",
        "load",
        sdf("""<model name="model_link_relative_to">
  <link name="L1"><pose>1 0 0 0 1.5707963267948966 0</pose></link>
  <link name="L2"><pose relative_to="">2 0 0 0 0 0</pose></link>
  <link name="L2a"><pose relative_to="__model__">12 0 0 0 0 0</pose></link>
  <link name="L3"><pose relative_to="L1">3 0 0 0 0 0</pose></link>
</model>"""),
        facts=(F("count links", 4),),
    ),
    case(
        MODEL_DOM,
        "DOMLink.NestedModelPoseRelativeTo",
        "load",
        sdf("""<model name="model_nested_model_relative_to">
  <link name="L"/>
  <model name="M1"><pose>1 0 0 0 1.5707963267948966 0</pose><link name="L"/></model>
  <model name="M2"><pose relative_to="">2 0 0 0 0 0</pose><link name="L"/></model>
  <model name="M3"><pose relative_to="M1">3 0 0 0 0 0</pose><link name="L"/></model>
</model>"""),
        "model_nested_model_relative_to.sdf",
        facts=(
            F("name", "model_nested_model_relative_to"),
            F("link L", True),
            F("link M1::L", True),
            F("link M3::L", True),
            F("count joints", 0),
        ),
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadJointNestedParentChild",
        "load",
        sdf(
            """<model name="joint_nested_parent_child">
  <model name="M1">
    <link name="L1"><pose>0 0 1 0 0 0</pose></link>
    <link name="L2"><pose>1 1 0 0 0 0</pose></link>
    <frame name="F1"><pose>1 0 0 0 0 0</pose></frame>
    <model name="M2"><pose>0 0 1 1.570796326790 0 0</pose><link name="L1"/></model>
  </model>
  <link name="L1"><pose>0 0 10 0 1.57079632679 0</pose></link>
  <frame name="F1" attached_to="M1::L1"><pose>1 0 0 0 0 0</pose></frame>
  <joint name="J1" type="fixed"><pose>1 0 0 0 0 0</pose><parent>M1::L1</parent><child>L1</child></joint>
  <joint name="J2" type="fixed"><pose>0 1 0 0 0 0</pose><parent>F1</parent><child>L1</child></joint>
  <joint name="J3" type="fixed"><pose>0 0 1 0 0 0</pose><parent>L1</parent><child>M1::L2</child></joint>
  <joint name="J4" type="fixed"><pose>0 0 1 0 0 0</pose><parent>L1</parent><child>M1::F1</child></joint>
  <joint name="J5" type="fixed"><pose>0 0 1 0 0 0</pose><parent>L1</parent><child>M1::M2</child></joint>
</model>""",
            "1.8",
        ),
        "joint_nested_parent_child.sdf",
        facts=(
            F("joint J1 parent", "M1::L1"),
            F("joint J1 child", "L1"),
            F("joint J2 parent", "M1::L1"),
            F("joint J2 child", "L1"),
            F("joint J3 parent", "L1"),
            F("joint J3 child", "M1::L2"),
            F("joint J4 parent", "L1"),
            F("joint J4 child", "M1::L1"),
            F("joint J5 parent", "L1"),
            F("joint J5 child", "M1::M2::L1"),
            F("joint J3 origin.xyz", relative(TOP_L1, M1_L2)[:3]),
            F("joint J5 origin.xyz", relative(TOP_L1, M2_L1)[:3]),
        ),
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadJointPoseRelativeTo",
        "load",
        sdf("""<model name="model_joint_relative_to">
  <link name="P1"><pose>1 0 0 0 1.5707963267948966 0</pose></link>
  <link name="C1"><pose>2 0 0 0 -1.5707963267948966 0</pose></link>
  <joint name="J1" type="fixed"><pose relative_to="">0 0 1 0 0 0</pose><parent>P1</parent><child>C1</child></joint>
  <link name="P2"><pose>3 0 0 0 1.5707963267948966 0</pose></link>
  <joint name="J2" type="fixed"><pose relative_to="P2">0 0 2 0 0 0</pose><parent>P2</parent><child>C2</child></joint>
  <link name="C2"><pose relative_to="J2">4 0 0 0 0 0</pose></link>
</model>"""),
        "model_joint_relative_to.sdf",
        facts=(
            F("count links", 4),
            F("count joints", 2),
            F("pose P1 C1", relative((1, 0, 0, 0, HALF_PI, 0), (2, 0, 0, 0, -HALF_PI, 0))),
            F("pose P2 C2", relative((3, 0, 0, 0, HALF_PI, 0), (5, 0, -4, 0, HALF_PI, 0))),
        ),
    ),
    check(
        "model_frame_relative_to.sdf",
        "load",
        sdf("""<model name="model_frame_relative_to">
  <link name="L"><pose>1 0 0 0 0 0</pose></link>
  <frame name="F0"><pose>0 1 0 0 0 0</pose></frame>
  <frame name="F1" attached_to="L"><pose>0 0 1 0 0 0</pose></frame>
  <frame name="F2" attached_to="L"><pose relative_to="">0 0 2 0 0 0</pose></frame>
  <frame name="F3"><pose relative_to="L">0 0 3 0 0 0</pose></frame>
  <frame name="F4"><pose relative_to="F3"/></frame>
</model>"""),
        facts=(F("count links", 1),),
    ),
    check(
        "model_frame_relative_to_joint.sdf",
        "load",
        sdf("""<model name="model_frame_relative_to_joint">
  <link name="P">
    <pose>1 0 0 0 0 0</pose>
    <inertial><pose relative_to="">0 0 0 0 0 0</pose></inertial>
    <collision name="P1"><pose>0 0 10 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry></collision>
    <collision name="P2"><pose relative_to="">0 0 11 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry>
    </collision>
    <visual name="vP1"><pose>0 0 10 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry></visual>
    <visual name="vP2"><pose relative_to="">0 0 11 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry></visual>
  </link>
  <link name="C">
    <pose>2 0 0 0 1.5707963267948966 0</pose>
    <collision name="P"><pose relative_to="P">0 0 12 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry>
    </collision>
    <collision name="J"><pose relative_to="J">0 0 13 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry>
    </collision>
    <collision name="F3"><pose relative_to="F3">0 0 14 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry>
    </collision>
    <collision name="F4"><pose relative_to="F4">0 0 15 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry>
    </collision>
    <visual name="vP"><pose relative_to="P">0 0 12 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry></visual>
    <visual name="vJ"><pose relative_to="J">0 0 13 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry></visual>
    <visual name="vF3"><pose relative_to="F3">0 0 14 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry>
    </visual>
    <visual name="vF4"><pose relative_to="F4">0 0 15 0 0 0</pose><geometry><sphere><radius>0.5</radius></sphere></geometry>
    </visual>
  </link>
  <joint name="J" type="fixed"><pose>0 3 0 0 -1.5707963267948966 0</pose><parent>P</parent><child>C</child></joint>
  <frame name="F1"><pose relative_to="P">0 0 1 0 0 0</pose></frame>
  <frame name="F2"><pose relative_to="C">0 0 2 0 0 0</pose></frame>
  <frame name="F3"><pose relative_to="J">0 0 3 0 1.5707963267948966 0</pose></frame>
  <frame name="F4"><pose relative_to="F3">0 0 4 0 -1.5707963267948966 0</pose></frame>
</model>"""),
        facts=(F("count links", 2), F("collisions P", 2), F("collisions C", 4), F("visuals C", 4)),
    ),
    check(
        "nested_model_cross_references.sdf",
        "load",
        sdf(
            """<model name="top_model">
  <frame name="top_frame"/>
  <link name="top_link"><pose relative_to="top_frame"/></link>
  <model name="mid_model">
    <pose relative_to="top_link"/>
    <link name="mid_link"/>
    <model name="bottom_model"><pose relative_to="mid_link"/><link name="bottom_link"/></model>
    <model name="bottom_model_2">
      <model name="mid_model"><link name="mid_link"/></model>
      <link name="bottom_link"><pose relative_to="mid_model::mid_link"/></link>
    </model>
    <frame name="mid_to_bottom" attached_to="bottom_model::bottom_link"/>
  </model>
</model>""",
            "1.8",
        ),
        facts=(F("count links", 5), F("link mid_model::bottom_model_2::mid_model::mid_link", True)),
    ),
    case(
        GEOMETRY_DOM,
        "DOMGeometry.Shapes",
        "load",
        SHAPES,
        "shapes.sdf",
        facts=(
            F("shape link collision box_col size", (3.0, 4.0, 5.0)),
            F("shape link visual box_vis size", (1.0, 2.0, 3.0)),
            F("shape link collision capsule_col type", "capsule"),
            F("shape link collision capsule_col radius", 0.2),
            F("shape link collision capsule_col length", 0.1),
            F("shape link visual capsule_vis radius", 2.1),
            F("shape link visual capsule_vis length", 10.2),
            F("shape link collision cone_col type", "cone"),
            F("shape link collision cone_col radius", 0.2),
            F("shape link collision cone_col length", 0.1),
            F("shape link visual cone_vis radius", 2.1),
            F("shape link visual cone_vis length", 10.2),
            F("shape link collision cylinder_col radius", 0.2),
            F("shape link collision cylinder_col length", 0.1),
            F("shape link visual cylinder_vis radius", 2.1),
            F("shape link visual cylinder_vis length", 10.2),
            F("shape link collision sphere_col radius", 23.4),
            F("shape link visual sphere_vis radius", 100.2),
            F("shape link collision mesh_col scale", (0.1, 0.2, 0.3)),
            F("shape link visual mesh_vis scale", (1.2, 2.3, 3.4)),
        ),
    ),
    case(
        GZ_TEST,
        "check_model_sdf.SDF",
        "load",
        sdf(
            """<model name="box">
  <pose>0 0 0.5 0 0 0</pose>
  <link name="link">
    <collision name="collision"><geometry><box><size>1 1 1</size></box></geometry></collision>
    <visual name="visual"><geometry><box><size>1 1 1</size></box></geometry></visual>
  </link>
</model>""",
            "1.5",
        ),
        "test/integration/model/box/model.sdf",
        facts=(F("count links", 1), F("shape link collision 0 size", (1.0, 1.0, 1.0))),
    ),
    case(
        GZ_TEST,
        "checkUnrecognizedElements.SDF",
        "load",
        sdf(
            """<model name="joint_incorrect_tags" some_attribute="staheousth">
  <link name="link">
    <pose>0 0 1 0 0 0</pose>
    <not_a_link_element>This should trigger a warning</not_a_link_element>
  </link>
  <not_a_model_element>This should also trigger a warning</not_a_model_element>
</model>
<not_an_sdf_element>Warnings time</not_an_sdf_element>""",
            "1.6",
        ),
        "unrecognized_elements.sdf",
        facts=(F("count links", 1),),
    ),
    # src/gz_TEST.cc, TEST(check, SDF): files refused, with the message expected
    check(
        "model_duplicate_links.sdf",
        "refuse",
        sdf(
            """<model name="duplicate_links">
  <link name="link"><pose>1 1 1 0 0 0</pose></link>
  <link name="link"><pose>2 2 2 0 0 0</pose></link>
</model>""",
            "1.6",
        ),
        r"link with name\[link\] already exists",
    ),
    check(
        "model_duplicate_joints.sdf",
        "refuse",
        sdf(
            """<model name="duplicate_joints">
  <link name="link1"/><link name="link2"/><link name="link3"/>
  <joint name="joint" type="fixed"><parent>link1</parent><child>link2</child></joint>
  <joint name="joint" type="fixed"><parent>link2</parent><child>link3</child></joint>
</model>""",
            "1.6",
        ),
        r"joint with name\[joint\] already exists",
    ),
    check(
        "link_duplicate_sibling_collisions.sdf",
        "refuse",
        sdf(
            """<model name="duplicate_sibling_collisions">
  <link name="link"><collision name="collision"/><collision name="collision"/></link>
</model>""",
            "1.6",
        ),
        r"collision with name\[collision\] already exists",
    ),
    check(
        "link_duplicate_sibling_visuals.sdf",
        "refuse",
        sdf(
            """<model name="duplicate_sibling_visuals">
  <link name="link"><visual name="visual"/><visual name="visual"/></link>
</model>""",
            "1.6",
        ),
        r"visual with name\[visual\] already exists",
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadInvalidChild",
        "refuse",
        sdf(
            """<model name="joint_invalid_child">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <link name="link2"/>
  <joint name="joint" type="fixed"><pose>0 0 3 0 0 0</pose><parent>link</parent><child>invalid</child></joint>
  <joint name="joint2" type="fixed"><parent>link2</parent><child>__model__</child></joint>
</model>""",
            "1.9",
        ),
        "joint_invalid_child.sdf",
        problem=r"Child frame with name\[invalid\] specified by joint with name\[joint\] not found",
    ),
    check(
        "joint_invalid_parent.sdf",
        "refuse",
        sdf(
            """<model name="joint_invalid_parent">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <joint name="joint" type="fixed"><pose>0 0 3 0 0 0</pose><parent>invalid</parent><child>link</child></joint>
</model>""",
            "1.6",
        ),
        r"parent frame with name\[invalid\] specified by joint with name\[joint\] not found",
    ),
    check(
        "joint_invalid_self_child.sdf",
        "refuse",
        sdf(
            """<model name="joint_invalid_self_child">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <joint name="self" type="fixed"><pose>0 0 3 0 0 0</pose><parent>link</parent><child>self</child></joint>
</model>""",
            "1.6",
        ),
        r"FrameAttachedToGraph cycle detected, already visited vertex \[joint_invalid_self_child::self\]",
    ),
    check(
        "joint_invalid_self_parent.sdf",
        "refuse",
        sdf(
            """<model name="joint_invalid_self_parent">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <joint name="self" type="fixed"><pose>0 0 3 0 0 0</pose><parent>self</parent><child>link</child></joint>
</model>""",
            "1.8",
        ),
        r"must not specify its own name as the parent frame",
    ),
    check(
        "joint_invalid_parent_same_as_child.sdf",
        "refuse",
        sdf(
            """<model name="joint_invalid_parent_same_as_child">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <joint name="joint" type="fixed"><pose>0 0 3 0 0 0</pose><parent>link</parent><child>link</child></joint>
</model>""",
            "1.6",
        ),
        r"must specify different frame names for parent and child, while \[link\] was specified for both",
    ),
    check(
        "joint_invalid_resolved_parent_same_as_child.sdf",
        "refuse",
        sdf(
            """<model name="joint_invalid_resolved_parent_same_as_child.sdf">
  <link name="L1"/>
  <joint name="J1" type="prismatic"><parent>L1</parent><child>J2</child><axis><xyz>1 0 0</xyz></axis></joint>
  <joint name="J2" type="prismatic"><parent>J1</parent><child>L2</child><axis><xyz>0 1 0</xyz></axis></joint>
  <link name="L2"/>
</model>""",
            "1.8",
        ),
        r"specified parent frame \[J1\] and child frame \[L2\] that both resolve to \[L2\]",
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadInvalidJointChildWorld",
        "refuse",
        sdf(
            """<model name="joint_child_world">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <joint name="joint" type="fixed"><pose>0 0 3 0 0 0</pose><parent>link</parent><child>world</child></joint>
</model>""",
            "1.6",
        ),
        "joint_child_world.sdf",
        problem=r"Joint with name\[joint\] specified invalid child link \[world\]",
    ),
    check(
        "model_invalid_canonical_link.sdf",
        "refuse",
        sdf("""<model name="model_invalid_canonical_link" canonical_link="link3">
  <link name="link1"><pose>1 0 0 0 0 0</pose></link>
  <link name="link2"><pose>0 2 0 0 0 0</pose></link>
</model>"""),
        r"canonical_link with name\[link3\] not found in model with name\[model_invalid_canonical_link\]",
    ),
    case(
        MODEL_DOM,
        "DOMModel.NoLinks",
        "refuse",
        sdf('<model name="model_without_links">\n</model>'),
        "model_without_links.sdf",
        problem=r"A model must have at least one link",
    ),
    case(
        MODEL_DOM,
        "DOMJoint.LoadInvalidNestedModelWithoutLinks",
        "refuse",
        sdf("""<model name="nested_without_links_invalid">
  <link name="link"/>
  <model name="nested_without_links1">
    <model name="nested_without_links2"><model name="nested_without_links3"><frame name="F"/></model></model>
  </model>
</model>"""),
        "nested_without_links_invalid.sdf",
        problem=r"A model must have at least one link",
    ),
    check(
        "model_invalid_reserved_names.sdf",
        "refuse",
        sdf("""<model name="model_invalid_reserved_names">
  <link name="world"/>
  <link name="__link__">
    <pose>0 0 0 0 0 0</pose>
    <collision name="__collision__"><geometry/></collision>
    <visual name="__visual__"><geometry/></visual>
  </link>
  <joint name="__joint__" type="fixed"><parent>world</parent><child>__link__</child></joint>
</model>"""),
        r"The supplied link name \[world\] is reserved",
    ),
    check(
        "model_frame_invalid_attached_to.sdf",
        "refuse",
        sdf("""<model name="model_frame_invalid_attached_to">
  <link name="L"/>
  <frame name="F1" attached_to="L"/>
  <frame name="F2" attached_to="F1"/>
  <frame name="F3" attached_to="A"/>
</model>"""),
        r"attached_to name\[A\] specified by frame with name\[F3\] does not match",
    ),
    check(
        "model_frame_invalid_attached_to_cycle.sdf",
        "refuse",
        sdf("""<model name="model_frame_invalid_attached_to_cycle">
  <link name="L"/>
  <frame name="F1" attached_to="F2"/>
  <frame name="F2" attached_to="F1"/>
</model>"""),
        r"FrameAttachedToGraph cycle detected, already visited vertex \[model_frame_invalid_attached_to_cycle::F[12]\]",
    ),
    check(
        "model_invalid_link_relative_to.sdf",
        "refuse",
        sdf("""<model name="model_invalid_link_relative_to">
  <link name="L"><pose relative_to="A">1 0 0 0 0 0</pose></link>
  <link name="self_cycle"><pose relative_to="self_cycle">2 0 0 0 0 0</pose></link>
</model>"""),
        r"relative_to name\[(A\] specified by link with name\[L\] does not match|self_cycle\] is identical)",
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadInvalidJointPoseRelativeTo",
        "refuse",
        sdf("""<model name="model_invalid_joint_relative_to">
  <link name="P"/>
  <link name="C"/>
  <joint name="Jcycle" type="fixed"><pose relative_to="Jcycle">0 1 0 0 0 0</pose><parent>P</parent><child>C</child></joint>
  <joint name="J" type="fixed"><pose relative_to="A">0 2 0 0 0 0</pose><parent>P</parent><child>C</child></joint>
</model>"""),
        "model_invalid_joint_relative_to.sdf",
        problem=r"relative_to name\[(Jcycle\] is identical to joint name\[Jcycle\]|A\] specified by joint with name\[J\])",
    ),
    check(
        "model_invalid_frame_relative_to.sdf",
        "refuse",
        sdf("""<model name="model_invalid_frame_relative_to">
  <link name="L"><pose>1 0 0 0 0 0</pose></link>
  <frame name="F"><pose relative_to="A">0 1 0 0 0 0</pose></frame>
  <frame name="cycle"><pose relative_to="cycle">0 2 0 0 0 0</pose></frame>
</model>"""),
        r"relative_to name\[(A\] specified by frame with name\[F\]|cycle\] is identical to frame name\[cycle\])",
    ),
    check(
        "model_invalid_frame_relative_to_cycle.sdf",
        "refuse",
        sdf("""<model name="model_invalid_frame_relative_to_cycle">
  <link name="L"><pose>1 0 0 0 0 0</pose></link>
  <frame name="F1"><pose relative_to="F2">0 1 0 0 0 0</pose></frame>
  <frame name="F2"><pose relative_to="F1">0 2 0 0 0 0</pose></frame>
</model>"""),
        r"PoseRelativeToGraph cycle detected, already visited vertex \[model_invalid_frame_relative_to_cycle::F[12]\]",
    ),
    check(
        "model_invalid_placement_frame.sdf",
        "refuse",
        sdf(
            """<model name="model_invalid_placement_frame" placement_frame="link3">
  <link name="link1"><pose>1 0 0 0 0 0</pose></link>
  <link name="link2"><pose>0 2 0 0 0 0</pose></link>
</model>""",
            "1.8",
        ),
        r"unable to find unique frame with name \[link3\] in graph",
    ),
    check(
        "model_invalid_root_reference.sdf",
        "refuse",
        sdf(
            """<model name="model_invalid_root_reference">
  <link name="link1"><pose relative_to="__root__">1 0 0 0 0 0</pose></link>
  <frame name="frame1" attached_to="__root__"/>
</model>""",
            "1.8",
        ),
        r"'__root__' is reserved; it cannot be used as a value of attribute \[(relative_to|attached_to)\]",
    ),
    check(
        "model_invalid_top_level_frame.sdf",
        "refuse",
        sdf(
            """<model name="M">
  <pose relative_to="some_frame"/>
  <link name="L"/>
</model>""",
            "1.8",
        ),
        r"Attribute //pose\[@relative_to\] of top level model must be left empty, found //pose\[@relative_to='some_frame'\]",
    ),
    # test/integration/model_dom.cc
    case(
        MODEL_DOM,
        "DOMRoot.LoadDoublePendulum",
        "load",
        DOUBLE_PENDULUM,
        "double_pendulum.sdf",
        facts=(
            F("name", "double_pendulum_with_base"),
            F("count links", 3),
            F("count joints", 2),
            F("link base", True),
            F("link upper_link", True),
            F("link lower_link", True),
            F("joint upper_joint parent", "base"),
            F("joint upper_joint child", "upper_link"),
            F("joint lower_joint parent", "upper_link"),
            F("joint lower_joint child", "lower_link"),
            F("joint upper_joint axis", (1.0, 0.0, 0.0)),
            F("inertial base mass", 100.0),
            F("inertial base ixx", 1.0),
            F("inertial base ixy", 0.0),
            F("inertial upper_link mass", 1.0),
            F("inertial upper_link origin.xyz", (0.0, 0.0, 0.5)),
            F("pose base upper_link", (0, 0, 2.1, -1.5708, 0, 0)),
            F("pose base lower_link", (0.25, 1.0, 2.1, -2, 0, 0)),
        ),
    ),
    case(
        MODEL_DOM,
        "DOMRoot.MultiNestedModel",
        "load",
        sdf("""<model name="outer_model">
  <link name="outer_link"/>
  <joint name="outer_joint" type="fixed"><parent>world</parent><child>outer_link</child></joint>
  <frame name="outer_frame"/>
  <model name="mid_model">
    <pose>1 0 0 0 1.5707963267948966 0</pose>
    <link name="mid_link"/>
    <joint name="mid_joint" type="fixed"><parent>world</parent><child>mid_link</child></joint>
    <frame name="mid_frame"/>
    <model name="inner_model">
      <link name="inner_link"/>
      <joint name="inner_joint" type="fixed"><parent>world</parent><child>inner_link</child></joint>
      <frame name="inner_frame"/>
    </model>
  </model>
</model>"""),
        "model_multi_nested_model.sdf",
        facts=(
            F("name", "outer_model"),
            F("count links", 3),
            F("count joints", 3),
            F("link outer_link", True),
            F("link mid_model::mid_link", True),
            F("link mid_model::inner_model::inner_link", True),
            F("joint mid_model::inner_model::inner_joint child", "mid_model::inner_model::inner_link"),
            F("joint outer_joint parent", "world"),
        ),
    ),
    case(
        MODEL_DOM,
        "DOMRoot.PartiallyFlattenedModel",
        "load",
        sdf("""<model name='MP'>
  <frame name='M1::__model__' attached_to='M1::L1'><pose relative_to='__model__'>0 0 0 0 -0 0</pose></frame>
  <link name='M1::L1'><pose relative_to='M1::__model__'>0 0 0 0 -0 0</pose></link>
  <model name='M1::M2'><link name='L2'/></model>
</model>"""),
        "partially_flattened.sdf",
        facts=(F("name", "MP"), F("link M1::L1", True), F("count joints", 0)),
    ),
    # test/integration/joint_dom.cc and joint_axis_dom.cc
    case(
        JOINT_DOM,
        "DOMJoint.Complete",
        "load",
        JOINT_COMPLETE,
        "joint_complete.sdf",
        facts=(
            F("count joints", 9),
            F("joint revolute_joint type", "revolute"),
            F("joint ball_joint type", "ball"),
            F("joint continuous_joint type", "continuous"),
            F("joint fixed_joint type", "fixed"),
            F("joint gearbox_joint type", "gearbox"),
            F("joint prismatic_joint type", "prismatic"),
            F("joint revolute2_joint type", "revolute2"),
            F("joint screw_joint type", "screw"),
            F("joint universal_joint type", "universal"),
            F("joint revolute_joint axis", (0.0, 0.0, 1.0)),
            F("joint revolute_joint limit.lower", -0.5),
            F("joint revolute_joint limit.upper", 0.5),
            F("joint revolute_joint limit.effort", 123.4),
            F("joint revolute_joint limit.velocity", 12.0),
        ),
    ),
    case(
        JOINT_DOM,
        "DOMJoint.LoadLinkJointSameName16Valid",
        "load",
        sdf(
            """<model name="link_joint_same_name">
  <link name="base"><pose>1 0 0 0 0 0</pose></link>
  <link name="attachment"><pose>0 2 0 0 0 0</pose></link>
  <joint name="attachment" type="fixed"><pose>0 0 3 0 0 0</pose><parent>base</parent><child>attachment</child></joint>
</model>""",
            "1.6",
        ),
        "model_link_joint_same_name.sdf",
        facts=(
            F("name", "link_joint_same_name"),
            F("count links", 2),
            F("count joints", 1),
            F("link base", True),
            F("link attachment", True),
            F("joint attachment_joint child", "attachment"),
            F("pose base attachment", (-1, 2, 0, 0, 0, 0)),
        ),
    ),
    case(
        JOINT_DOM,
        "DOMJoint.Sensors",
        "load",
        sdf("""<model name="model">
  <link name="link1"/>
  <link name="link2"/>
  <joint name="joint" type="fixed">
    <parent>link1</parent>
    <child>link2</child>
    <sensor name="force_torque_sensor" type="force_torque">
      <pose>10 11 12 0 0 0</pose>
      <force_torque><frame>parent</frame><measure_direction>parent_to_child</measure_direction></force_torque>
    </sensor>
  </joint>
</model>"""),
        "joint_sensors.sdf",
        facts=(F("name", "model"), F("count joints", 1)),
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.XyzExpressedIn",
        "load",
        sdf("""<model name="model_joint_axis_expressed_in">
  <link name="P1"><pose>1 0 0 0 1.5707963267948966 0</pose></link>
  <link name="C1"><pose>2 0 0 0 -1.5707963267948966 0</pose></link>
  <joint name="J1" type="revolute">
    <pose relative_to="">0 0 1 0 0 0</pose><parent>P1</parent><child>C1</child><axis><xyz>0 0 1</xyz></axis>
  </joint>
  <link name="P2"><pose>3 0 0 0 1.5707963267948966 0</pose></link>
  <joint name="J2" type="revolute">
    <pose relative_to="P2">0 0 2 0 0 0</pose><parent>P2</parent><child>C2</child>
    <axis><xyz expressed_in="__model__">0 0 1</xyz></axis>
  </joint>
  <link name="C2"><pose relative_to="J2">4 0 0 0 0 0</pose></link>
</model>"""),
        "model_joint_axis_expressed_in.sdf",
        facts=(
            F("name", "model_joint_axis_expressed_in"),
            F("count links", 4),
            F("count joints", 2),
            F("joint J1 type", "revolute"),
            F("joint J2 type", "revolute"),
            F("joint J1 axis", (0.0, 0.0, 1.0)),
            F("joint J2 axis", (-1.0, 0.0, 0.0)),
        ),
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.InvalidExpressedIn",
        "refuse",
        sdf(
            """<model name="joint_axis_invalid_expressed_in">
  <link name="link"><pose>0 0 1 0 0 0</pose></link>
  <joint name="joint" type="revolute">
    <pose>0 0 3 0 0 0</pose><parent>world</parent><child>link</child>
    <axis><xyz expressed_in="invalid">0 0 1</xyz></axis>
  </joint>
</model>""",
            "1.6",
        ),
        "joint_axis_invalid_expressed_in.sdf",
        problem=r"axis xyz expressed-in frame with name\[invalid\] specified by joint with name\[joint\] not found",
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.XyzNormalization",
        "refuse",
        sdf(
            """<model name="test">
  <link name="link1"/><link name="link2"/><link name="link3"/><link name="link4"/><link name="link5"/><link name="link6"/>
  <joint name="joint1" type="revolute"><child>link1</child><parent>link2</parent><axis><xyz>0 0 1</xyz></axis></joint>
  <joint name="joint2" type="revolute"><child>link3</child><parent>link4</parent><axis><xyz>10 0 0</xyz></axis></joint>
  <joint name="joint3" type="universal">
    <child>link4</child><parent>link5</parent><axis><xyz>-10 0 0</xyz></axis><axis2><xyz>0 10 0</xyz></axis2>
  </joint>
  <joint name="joint4" type="revolute"><child>link5</child><parent>link6</parent><axis><xyz>0 0 0</xyz></axis></joint>
</model>""",
            "1.6",
        ),
        "joint_axis_xyz_normalization.sdf",
        problem=r"The norm of the xyz vector cannot be zero",
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.ParseMimic",
        "load",
        sdf(
            MIMIC_HEADER
            + """
  <joint name="source_joint" type="revolute">
    <pose>1 0 0 0 0 0</pose><child>link1</child><parent>link2</parent><axis><xyz>0 0 1</xyz></axis>
  </joint>
  <joint name="follow_joint" type="revolute">
    <pose>2 0 0 0 0 0</pose><child>link1</child><parent>link3</parent>
    <axis><xyz>0 0 1</xyz>
      <mimic joint="source_joint"><multiplier>4</multiplier><offset>2</offset><reference>3</reference></mimic>
    </axis>
  </joint>
</model>""",
            "1.11",
        ),
        None,
        facts=(
            F("joint follow_joint mimic.joint", "source_joint"),
            F("joint follow_joint mimic.multiplier", 4.0),
            F("joint follow_joint mimic.offset", 2.0),
        ),
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.ParseInvalidSelfMimic",
        "refuse",
        sdf(
            """<model name="test">
  <link name="link1"/>
  <link name="link2"/>
  <joint name="self_mimic" type="universal">
    <pose>1 0 0 0 0 0</pose><child>link1</child><parent>link2</parent>
    <axis><xyz>0 0 1</xyz>
      <mimic joint="self_mimic"><multiplier>4</multiplier><offset>2</offset><reference>3</reference></mimic></axis>
    <axis2><xyz>1 0 0</xyz>
      <mimic joint="self_mimic" axis="axis2"><multiplier>4</multiplier><offset>2</offset><reference>3</reference></mimic>
    </axis2>
  </joint>
</model>""",
            "1.11",
        ),
        None,
        problem=r"Axis with name \[axis\] in joint with name \[self_mimic\] cannot mimic itself",
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.ParseMimicInvalidLeaderJointName",
        "refuse",
        sdf(
            """<model name="test">
  <link name="link1"/>
  <link name="link2"/>
  <joint name="joint" type="universal">
    <pose>1 0 0 0 0 0</pose><child>link1</child><parent>link2</parent>
    <axis><xyz>0 0 1</xyz>
      <mimic joint="invalid"><multiplier>4</multiplier><offset>2</offset><reference>3</reference></mimic></axis>
    <axis2><xyz>1 0 0</xyz>
      <mimic joint="invalid"><multiplier>4</multiplier><offset>2</offset><reference>3</reference></mimic></axis2>
  </joint>
</model>""",
            "1.11",
        ),
        None,
        problem=r"A joint with name\[invalid\] specified by an axis mimic in joint with name\[joint\] not found in model",
    ),
    case(
        AXIS_DOM,
        "DOMJointAxis.ParseMimicInvalidLeaderAxis",
        "refuse",
        sdf(
            MIMIC_HEADER
            + """
  <joint name="leader" type="revolute">
    <pose>0 0 1 0 0 0</pose><child>link1</child><parent>link2</parent><axis><xyz>0 0 1</xyz></axis>
  </joint>
  <joint name="follower" type="universal">
    <pose>1 0 0 0 0 0</pose><child>link2</child><parent>link3</parent>
    <axis><xyz>0 0 1</xyz>
      <mimic joint="leader" axis="invalid"><multiplier>4</multiplier><offset>2</offset><reference>3</reference></mimic></axis>
    <axis2><xyz>1 0 0</xyz>
      <mimic joint="leader" axis="axis2"><multiplier>4</multiplier><offset>2</offset><reference>3</reference></mimic></axis2>
  </joint>
</model>""",
            "1.11",
        ),
        None,
        problem=r"specified an invalid leader axis name \[invalid\]",
    ),
    # test/integration/link_dom.cc
    case(
        LINK_DOM,
        "DOMLink.InertialComplete",
        "load",
        sdf(
            """<model name="model">
  <link name="link">
    <inertial>
      <pose>0.01 0 0.02 0 0 0</pose>
      <mass>17.982</mass>
      <inertia><ixx>0.125569</ixx><ixy>0.0008</ixy><ixz>-0.000499757</ixz><iyy>0.0972062</iyy><iyz>-0.0005</iyz>
        <izz>0.117937</izz></inertia>
      <fluid_added_mass><xx>11.0</xx><xy>12.0</xy><xz>13.0</xz><xp>14.0</xp><xq>15.0</xq><xr>16.0</xr><yy>22.0</yy>
        <yz>23.0</yz><yp>24.0</yp><yq>25.0</yq><yr>26.0</yr><zz>33.0</zz><zp>34.0</zp><zq>35.0</zq><zr>36.0</zr>
        <pp>44.0</pp><pq>45.0</pq><pr>46.0</pr><qq>55.0</qq><qr>56.0</qr><rr>66.0</rr></fluid_added_mass>
    </inertial>
  </link>
</model>""",
            "1.6",
        ),
        "inertial_complete.sdf",
        facts=(
            F("inertial link mass", 17.982),
            F("inertial link ixx", 0.125569),
            F("inertial link iyy", 0.0972062),
            F("inertial link izz", 0.117937),
            F("inertial link ixy", 0.0008),
            F("inertial link ixz", -0.000499757),
            F("inertial link iyz", -0.0005),
            F("inertial link origin.xyz", (0.01, 0.0, 0.02)),
        ),
    ),
    case(
        LINK_DOM,
        "DOMLink.InertialInvalid",
        "refuse",
        sdf(
            """<model name="model">
  <link name="link">
    <inertial>
      <pose>0.01 0 0.02 0 0 0</pose>
      <mass>-1</mass>
      <inertia><ixx>0.125569</ixx><ixy>0.0008</ixy><ixz>-0.000499757</ixz><iyy>0.0972062</iyy><iyz>-0.0005</iyz>
        <izz>0.117937</izz></inertia>
    </inertial>
  </link>
</model>""",
            "1.6",
        ),
        "inertial_invalid.sdf",
        problem=r"GC50[2-4].*(mass|inertia)",
    ),
    # test/integration/root_dom.cc
    case(
        ROOT_DOM,
        "DOMRoot.InvalidSDF",
        "refuse",
        '<?xml version="1.0" ?>\n<sdfgarbage>\n</sdfgarbage>\n',
        "empty_invalid.sdf",
        problem=r"not an SDFormat document",
    ),
    case(
        ROOT_DOM,
        "DOMRoot.NoVersion",
        "refuse",
        '<?xml version="1.0" ?>\n<sdf>\n</sdf>\n',
        "empty_noversion.sdf",
        problem=r"version",
    ),
)
