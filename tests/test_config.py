"""Configuration files: discovery, every key, validation, and flags over the file."""

from __future__ import annotations

from pathlib import Path

import pytest

from geomcheck.cli import build_parser, main, settings_for
from geomcheck.config import Config, discover_config, find_config, load_config, merge, resolve_selector
from geomcheck.diagnostics import Diagnostic, Severity
from geomcheck.errors import UsageError
from geomcheck.model import SourceLocation
from geomcheck.pipeline import apply_selection


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def config_of(tmp_path: Path, text: str) -> Config:
    return load_config(write(tmp_path / "geomcheck.toml", text))


def diag(code: str, *, link: str | None = None, joint: str | None = None, sev: Severity = Severity.ERROR) -> Diagnostic:
    return Diagnostic(code, "x", sev, "m", "h", link=link, joint=joint, location=SourceLocation("r.urdf", 1))


def selected(config: Config, diagnostics: list[Diagnostic]) -> list[tuple[str, str]]:
    return [(d.code, d.severity.value) for d in apply_selection(diagnostics, config.selection())]


DIAGS = [diag("GC101"), diag("GC301", link="base_link"), diag("GC302", link="wheel"), diag("GC501", link="wheel")]

# --- discovery ---------------------------------------------------------------------------


def test_found_from_the_description_folder_upwards(tmp_path: Path) -> None:
    cfg = write(tmp_path / "repo" / "geomcheck.toml", 'fail-on = "warning"\n')
    description = write(tmp_path / "repo" / "pkg" / "robots" / "r.urdf", "<robot/>")
    assert find_config(description) == cfg
    assert discover_config(description).fail_on is Severity.WARNING


def test_geomcheck_toml_wins_over_pyproject_in_one_folder(tmp_path: Path) -> None:
    write(tmp_path / "pyproject.toml", '[tool.geomcheck]\nfail-on = "info"\n')
    own = write(tmp_path / "geomcheck.toml", 'fail-on = "warning"\n')
    assert find_config(tmp_path / "r.urdf") == own


def test_pyproject_tool_table_is_read(tmp_path: Path) -> None:
    project = write(tmp_path / "pyproject.toml", '[project]\nname = "x"\n[tool.geomcheck]\nfail-on = "info"\n')
    assert find_config(tmp_path / "r.urdf") == project
    assert load_config(project).fail_on is Severity.INFO


def test_pyproject_without_tool_table_is_passed_over(tmp_path: Path) -> None:
    outer = write(tmp_path / "geomcheck.toml", 'fail-on = "info"\n')
    write(tmp_path / "pkg" / "pyproject.toml", '[project]\nname = "x"\n')
    assert find_config(tmp_path / "pkg" / "r.urdf") == outer


def test_search_stops_at_the_git_root(tmp_path: Path) -> None:
    write(tmp_path / "geomcheck.toml", 'fail-on = "info"\n')
    (tmp_path / "repo" / ".git").mkdir(parents=True)
    assert find_config(tmp_path / "repo" / "robots" / "r.urdf") is None
    assert discover_config(tmp_path / "repo" / "robots" / "r.urdf") == Config()


def test_the_git_root_itself_is_searched(tmp_path: Path) -> None:
    (tmp_path / ".git").mkdir()
    cfg = write(tmp_path / "geomcheck.toml", "")
    assert find_config(tmp_path / "robots" / "r.urdf") == cfg


# --- every key -----------------------------------------------------------------------------


def test_select_by_code_and_family_name(tmp_path: Path) -> None:
    config = config_of(tmp_path, 'select = ["fit", "GC501"]\n')
    assert config.select == ("GC3", "GC501")
    assert selected(config, DIAGS) == [("GC301", "error"), ("GC302", "error"), ("GC501", "error")]


def test_ignore(tmp_path: Path) -> None:
    config = config_of(tmp_path, 'ignore = ["GC3"]\n')
    assert selected(config, DIAGS) == [("GC101", "error"), ("GC501", "error")]


def test_extend_select_adds_to_select(tmp_path: Path) -> None:
    config = config_of(tmp_path, 'select = ["GC1"]\nextend-select = ["inertia"]\n')
    assert selected(config, DIAGS) == [("GC101", "error"), ("GC501", "error")]


def test_severity_overrides(tmp_path: Path) -> None:
    config = config_of(tmp_path, '[severity]\nGC3 = "warning"\nGC5 = "info"\nGC501 = "warning"\n')
    assert selected(config, DIAGS) == [
        ("GC101", "error"),
        ("GC301", "warning"),
        ("GC302", "warning"),
        ("GC501", "warning"),
    ]


def test_thresholds_of_a_family(tmp_path: Path) -> None:
    config = config_of(tmp_path, "[thresholds.fit]\nprotrusion_tolerance_m = 0.02\nsurface_samples = 500\n")
    options = config.to_options()
    assert options.thresholds.fit.protrusion_tolerance_m == 0.02
    assert options.thresholds.fit.surface_samples == 500
    assert options.thresholds.inertia == type(options.thresholds.inertia)()


def test_thresholds_accept_kebab_case(tmp_path: Path) -> None:
    config = config_of(tmp_path, "[thresholds.self-collision]\nclearance-margin-m = 0.01\n")
    assert config.to_options().thresholds.self_collision.clearance_margin_m == 0.01


def test_unknown_threshold_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match="protrusion_tolerance"):
        config_of(tmp_path, "[thresholds.fit]\nprotrusion_tolerance = 0.02\n")
    with pytest.raises(UsageError, match="threshold family 'fitt'"):
        config_of(tmp_path, "[thresholds.fitt]\nseed = 1\n")


def test_per_link_ignores(tmp_path: Path) -> None:
    config = config_of(tmp_path, '[per-link-ignores]\nwheel = ["GC3"]\n')
    assert selected(config, DIAGS) == [("GC101", "error"), ("GC301", "error"), ("GC501", "error")]


def test_per_joint_ignores(tmp_path: Path) -> None:
    config = config_of(tmp_path, '[per-joint-ignores]\nfl_caster_rotation_joint = ["GC120"]\n')
    found = [diag("GC120", joint="fl_caster_rotation_joint"), diag("GC120", joint="other")]
    assert [d.joint for d in apply_selection(found, config.selection())] == ["other"]


def test_packages_relative_to_the_file(tmp_path: Path) -> None:
    (tmp_path / "deps" / "pr2_description").mkdir(parents=True)
    config = config_of(tmp_path, '[packages]\npr2_description = "deps/pr2_description"\n')
    assert config.packages == {"pr2_description": tmp_path.resolve() / "deps" / "pr2_description"}


def test_package_that_is_not_a_folder_is_an_error(tmp_path: Path) -> None:
    with pytest.raises(UsageError, match=r"packages\.pr2_description: not a directory"):
        config_of(tmp_path, '[packages]\npr2_description = "nowhere"\n')


def test_search_paths(tmp_path: Path) -> None:
    (tmp_path / "src").mkdir()
    assert config_of(tmp_path, 'search = ["src"]\n').search == (tmp_path.resolve() / "src",)


def test_xacro_args(tmp_path: Path) -> None:
    config = config_of(tmp_path, '[args]\nprefix = "left_"\nuse_gpu = true\nscale = 2\n')
    assert config.to_options().args == {"prefix": "left_", "use_gpu": "true", "scale": "2"}


def test_srdf(tmp_path: Path) -> None:
    write(tmp_path / "config" / "r.srdf", "<robot/>")
    config = config_of(tmp_path, 'srdf = "config/r.srdf"\n')
    assert config.to_options().srdf == tmp_path.resolve() / "config" / "r.srdf"
    with pytest.raises(UsageError, match="srdf: no such file"):
        config_of(tmp_path, 'srdf = "missing.srdf"\n')


def test_pose_and_pose_name(tmp_path: Path) -> None:
    config = config_of(tmp_path, 'pose-name = "home"\n[pose]\nelbow = 1.5\nwrist = 0\n')
    options = config.to_options()
    assert options.pose == {"elbow": 1.5, "wrist": 0.0}
    assert options.pose_name == "home"


def test_matrix_options(tmp_path: Path) -> None:
    config = config_of(tmp_path, 'matrix = true\nsamples = 2000\nseed = 7\nbackend = "fcl"\nsweep = false\n')
    options = config.to_options()
    assert (options.matrix, options.samples, options.seed, options.backend, options.sweep) == (
        True,
        2000,
        7,
        "fcl",
        False,
    )


def test_semantics_option(tmp_path: Path) -> None:
    assert config_of(tmp_path, 'semantics = "pinocchio"\n').to_options().semantics == "pinocchio"
    with pytest.raises(UsageError, match=r"semantics: invalid value 'drake'.*moveit, pinocchio"):
        config_of(tmp_path, 'semantics = "drake"\n')


def test_defaults_without_configuration() -> None:
    options = Config().to_options()
    assert (options.matrix, options.sweep, options.backend, options.fail_on) == (False, True, "coal", Severity.ERROR)
    assert options.semantics == "moveit"
    assert options.selection.select == ("ALL",)


def test_fail_on(tmp_path: Path) -> None:
    assert config_of(tmp_path, 'fail-on = "warning"\n').to_options().fail_on is Severity.WARNING


def test_output_format(tmp_path: Path) -> None:
    assert config_of(tmp_path, 'output-format = "concise"\n').output_format == "concise"


def test_baseline_relative_to_the_file(tmp_path: Path) -> None:
    assert config_of(tmp_path, 'baseline = "geomcheck-baseline.json"\n').baseline == (
        tmp_path.resolve() / "geomcheck-baseline.json"
    )


# --- validation ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ('selct = ["GC3"]\n', "unknown configuration key 'selct'; did you mean 'select'?"),
        ('select = ["GC3O1"]\n', "unknown rule code or family 'GC3O1'"),
        ('ignore = ["fitt"]\n', "did you mean 'fit'?"),
        ('[severity]\nGC101 = "fatal"\n', "severity.GC101: invalid value 'fatal'"),
        ('[severity]\nGC1O1 = "error"\n', "severity: unknown rule code or family 'GC1O1'; did you mean 'GC101'?"),
        ('samples = "many"\n', "samples must be an integer, got 'many'"),
        ("samples = 0\n", "samples must be at least 1"),
        ('backend = "bullet"\n', "backend: invalid value 'bullet'"),
        ("matrix = 1\n", "matrix must be true or false"),
        ('select = "GC3"\nfail-on = "fatal"\n', "fail-on: invalid value 'fatal'"),
        ("select = [\n", "invalid TOML"),
    ],
)
def test_invalid_values_name_the_key(tmp_path: Path, text: str, expected: str) -> None:
    with pytest.raises(UsageError) as err:
        config_of(tmp_path, text)
    assert expected in str(err.value)
    assert str(tmp_path / "geomcheck.toml") in str(err.value)


def test_resolve_selector_accepts_names_and_all() -> None:
    assert resolve_selector("ALL") == "ALL"
    assert resolve_selector("gc3") == "GC3"
    assert resolve_selector("structure") == "GC1"


def test_unknown_key_exits_2_naming_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write(tmp_path / "geomcheck.toml", "fail_on = 'warning'\n")
    description = write(tmp_path / "r.urdf", '<robot name="r"><link name="a"/></robot>')
    assert main(["check", str(description)]) == 2
    err = capsys.readouterr().err
    assert "unknown configuration key 'fail_on'; did you mean 'fail-on'?" in err
    assert err.count("\n") == 1


def test_unknown_code_on_the_command_line_exits_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    description = write(tmp_path / "r.urdf", '<robot name="r"><link name="a"/></robot>')
    assert main(["check", "--no-config", "--select", "GC999", str(description)]) == 2
    assert "command line: --select: unknown rule code or family 'GC999'" in capsys.readouterr().err


# --- flags over the file -------------------------------------------------------------------


def settings(tmp_path: Path, *argv: str) -> Config:
    ns = build_parser().parse_args(["check", *argv, str(tmp_path / "r.urdf")])
    return settings_for(ns, ns.paths[0])


def test_flags_win_over_the_file(tmp_path: Path) -> None:
    write(tmp_path / "geomcheck.toml", 'fail-on = "info"\nbackend = "fcl"\nmatrix = true\nsamples = 5\n')
    config = settings(tmp_path, "--fail-on", "warning", "--backend", "coal", "--no-matrix", "--samples", "9")
    options = config.to_options()
    assert (options.fail_on, options.backend, options.matrix, options.samples) == (Severity.WARNING, "coal", False, 9)
    assert config.path == (tmp_path / "geomcheck.toml").resolve()


def test_select_flag_replaces_file_select_and_ignore(tmp_path: Path) -> None:
    write(tmp_path / "geomcheck.toml", 'select = ["GC1"]\nignore = ["GC3"]\n')
    config = settings(tmp_path, "--select", "GC3")
    assert selected(config, DIAGS) == [("GC301", "error"), ("GC302", "error")]


def test_ignore_and_extend_select_flags_add_to_the_file(tmp_path: Path) -> None:
    write(tmp_path / "geomcheck.toml", 'select = ["GC1", "GC3"]\nignore = ["GC101"]\n')
    config = settings(tmp_path, "--ignore", "fit", "--extend-select", "GC5")
    assert selected(config, DIAGS) == [("GC501", "error")]


def test_maps_merge_key_by_key(tmp_path: Path) -> None:
    write(tmp_path / "geomcheck.toml", '[args]\nprefix = "l_"\nside = "left"\n')
    assert settings(tmp_path, "--arg", "side=right").args == {"prefix": "l_", "side": "right"}


def test_config_flag_and_no_config(tmp_path: Path) -> None:
    write(tmp_path / "geomcheck.toml", 'fail-on = "info"\n')
    other = write(tmp_path / "ci" / "strict.toml", 'fail-on = "warning"\n')
    assert settings(tmp_path).fail_on is Severity.INFO
    assert settings(tmp_path, "--config", str(other)).fail_on is Severity.WARNING
    assert settings(tmp_path, "--no-config").fail_on is None


def test_merge_keeps_file_thresholds_per_field() -> None:
    low = Config(thresholds={"fit": {"min_coverage": 0.8, "max_slack": 3.0}})
    high = Config(thresholds={"fit": {"max_slack": 5.0}})
    assert merge(low, high).thresholds == {"fit": {"min_coverage": 0.8, "max_slack": 5.0}}
