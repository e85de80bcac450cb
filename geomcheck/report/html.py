"""HTML: one self-contained page (CSS, a little script and every picture inline as SVG).

The page needs no network and no script to be read; the script only adds conveniences
(expand/collapse all, opening collapsed sections for printing and on navigation, the
matrix read-out) and, with WebGL, the 3D view (three.js, inlined with its licence, draws
the ``scene`` section; without WebGL the section points to the orthographic views).
Same report, same bytes: :func:`render` uses nothing but the report.
"""

from __future__ import annotations

import functools
from importlib import resources

import jinja2
from markupsafe import Markup

from geomcheck.report.html_model import page_model
from geomcheck.report.model import Report

TEMPLATE_PACKAGE = "geomcheck.report"
TEMPLATE_DIR = "templates"


@functools.cache
def environment() -> jinja2.Environment:
    """The Jinja environment over the packaged templates: autoescaping, strict undefined."""
    return jinja2.Environment(
        loader=jinja2.PackageLoader(TEMPLATE_PACKAGE, TEMPLATE_DIR),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )


@functools.cache
def asset(name: str) -> Markup:
    """A packaged static file (``report.css``, ``report.js``) to inline verbatim."""
    return Markup(resources.files(TEMPLATE_PACKAGE).joinpath(TEMPLATE_DIR, name).read_text(encoding="utf-8"))


SCRIPT = "report.js"
# the 3D view's scripts, inlined only in a report with a ``scene`` section: three.js (the
# subset scripts/viewer/build.sh bundles, with its MIT licence) and the viewer that drives it
VIEW3D_SCRIPTS = ("three.min.js", "view3d.js")


def inline_scripts() -> tuple[str, ...]:
    """Every script a report may run, each as the template writes it in its ``<script>``
    element (a newline, then the file): what a Content-Security-Policy allows by hash."""
    return tuple("\n" + str(asset(name)) for name in (SCRIPT, *VIEW3D_SCRIPTS))


def render(report: Report) -> str:
    """The report as one HTML document."""
    page = page_model(report)
    template = environment().get_template("report.html.j2")
    scripts = [asset(name) for name in VIEW3D_SCRIPTS] if page["view3d"] else []
    return template.render(page=page, css=asset("report.css"), script=asset(SCRIPT), view3d_scripts=scripts)
