"""HTML: one self-contained page (CSS, a little script and every picture inline as SVG).

The page needs no network and no script to be read; the script only adds conveniences
(expand/collapse all, opening collapsed sections for printing and on navigation, the
matrix read-out). Same report, same bytes: :func:`render` uses nothing but the report.
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


def render(report: Report) -> str:
    """The report as one HTML document."""
    page = page_model(report)
    template = environment().get_template("report.html.j2")
    return template.render(page=page, css=asset("report.css"), script=asset("report.js"))
