"""URDF markup findings: unknown elements and attributes of the core, misplaced core elements,
extension markup, each kind grouped for the robot."""

from __future__ import annotations

from tests.load.urdf_sample import URDF


def test_misplaced_core_element_names_its_home(load) -> None:
    loaded = load(URDF.replace("<drake:proximity_properties/>", '<material name="blue"/>'))
    (d,) = loaded.diagnostics
    assert (d.code, d.severity.value) == ("GC105", "info")
    assert d.message == (
        "unknown element <material> inside <collision>; <material> belongs in <robot> or <visual> "
        "(a collision element has no appearance: every consumer ignores it)"
    )


def test_misplaced_origin_is_a_warning_unless_it_is_the_identity(load) -> None:
    shifted = load(URDF.replace('<link name="wheel"/>', '<link name="wheel"><origin xyz="0 0 0.1"/></link>'))
    (d,) = shifted.diagnostics
    assert (d.code, d.severity.value, d.link, d.about) == ("GC105", "warning", "wheel", "/origin")
    assert d.message == (
        "unknown element <origin> inside <link>; <origin> belongs in <collision> or <inertial> or <joint> or <visual>"
    )
    zero = '<link name="wheel"><origin rpy="0 0 0" xyz="0 0 0"/></link>'
    identity = load(URDF.replace('<link name="wheel"/>', zero))
    (d,) = identity.diagnostics
    assert (d.code, d.severity.value, d.link) == ("GC105", "info", "wheel")
    assert d.message.endswith("(an identity pose: it would change nothing where it belongs)")


def test_extension_markup_is_one_info_finding_per_kind_for_the_robot(load) -> None:
    surface = "<surface><friction><ode><mu>1</mu></ode></friction></surface>"
    text = URDF.replace("<drake:proximity_properties/>", surface).replace(
        '<cylinder radius="0.1" length="0.3"/></geometry>', f'<cylinder radius="0.1" length="0.3"/></geometry>{surface}'
    )
    text = text.replace(
        '<link name="wheel"/>',
        f'<link name="wheel"><collision><geometry><sphere radius="0.1"/></geometry>{surface}</collision></link>',
    )
    text = text.replace('<axis xyz="0 0 1"/>', '<axis xyz="0 0 1" rpy="0 0 0"/><joint_properties damping="0"/>')
    found = sorted((d.code, d.severity.value, d.link or d.joint, d.data.get("also")) for d in load(text).diagnostics)
    assert found == [
        ("GC105", "info", "base", ["base", "wheel"]),
        ("GC105", "info", "wheel_joint", None),
        ("GC106", "info", "wheel_joint", None),
    ]
    messages = sorted(d.message for d in load(text).diagnostics)
    assert messages[0] == (
        "unknown attribute 'rpy' on <axis> (URDF defines: xyz): extension markup no URDF consumer reads"
    )
    assert messages[2] == (
        "unknown element <surface> inside <collision>: extension markup no URDF consumer reads there "
        "(also in base, wheel)"
    )


def test_a_misspelt_name_stays_a_warning(load) -> None:
    (d,) = load(URDF.replace("<drake:proximity_properties/>", '<orign xyz="0 0 1"/>')).diagnostics
    assert (d.code, d.severity.value, d.data["suggestion"]) == ("GC105", "warning", "origin")
    (d,) = load(URDF.replace('<axis xyz="0 0 1"/>', '<axis xzy="0 0 1"/>')).diagnostics
    assert (d.code, d.severity.value, d.data["suggestions"]) == ("GC106", "warning", {"xzy": "xyz"})


def test_unknown_attributes_are_grouped_per_element(load) -> None:
    loaded = load(
        URDF.replace('<dynamics damping="0.1" friction="0.01"/>', '<dynamics dampin="0.1" Q="3" friction="0"/>')
    )
    (d,) = loaded.diagnostics
    assert d.code == "GC106" and d.joint == "wheel_joint"
    assert d.message == (
        "unknown attributes 'dampin' (did you mean 'damping'?), 'Q' on <dynamics> (URDF defines: damping, friction)"
    )
    assert d.data["suggestions"] == {"dampin": "damping"}


def test_attributes_a_known_tool_reads_are_extensions_not_typos(load) -> None:
    # Franka's friction model on <dynamics> (franka_description), PyBullet's concave and mask on <collision>
    franka = '<dynamics D="1" K="7000" damping="0.003" friction="0.0" mu_coulomb="0" mu_viscous="16"/>'
    text = URDF.replace('<dynamics damping="0.1" friction="0.01"/>', franka)
    text = text.replace("<collision><geometry><cylinder", '<collision concave="yes" mask="3"><geometry><cylinder')
    assert load(text).diagnostics == ()
    # a misspelt extension attribute is still a typo, offered the tool's name
    (d,) = load(text.replace('mu_viscous="16"', 'mu_viscos="16"')).diagnostics
    assert (d.code, d.joint, d.data["attributes"]) == ("GC106", "wheel_joint", ["mu_viscos"])
    assert d.data["suggestions"] == {"mu_viscos": "mu_viscous"}
    assert "'mu_viscos' (did you mean 'mu_viscous'?) on <dynamics>" in d.message
    # only where the tool writes them: K on <limit> is a typo
    (d,) = load(text.replace('<limit effort="10"', '<limit K="1" effort="10"')).diagnostics
    assert (d.code, d.data["attributes"]) == ("GC106", ["K"])


def test_isaac_gym_dont_collapse_is_an_extension(load) -> None:
    text = URDF.replace(
        '<joint name="wheel_joint" type="continuous">',
        '<joint name="wheel_joint" type="continuous" dont_collapse="true">',
    )
    assert load(text).diagnostics == ()


def test_a_grouped_finding_does_not_depend_on_the_order_of_the_links(load) -> None:
    surface = "<surface/>"
    first = f'<link name="a"><collision><geometry><sphere radius="0.1"/></geometry>{surface}</collision></link>'
    second = f'<link name="b"><collision><geometry><sphere radius="0.2"/></geometry>{surface}</collision></link>'
    texts = [f'<robot name="r">\n  {x}\n  {y}\n</robot>\n' for x, y in ((first, second), (second, first))]
    found = [[(d.link, d.message, d.data["also"]) for d in load(text).diagnostics] for text in texts]
    assert (
        found[0]
        == found[1]
        == [
            (
                "a",
                "unknown element <surface> inside <collision>: extension markup no URDF consumer reads there"
                " (also in b)",
                ["b"],
            )
        ]
    )
