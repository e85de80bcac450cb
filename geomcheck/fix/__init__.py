"""``geomcheck fix``: a description's findings fixed, each fix checked again before it
reaches the user's files.

The floor above the pipeline, since it runs the checks: :mod:`geomcheck.fix.run` checks the
description and plans its fixes, :mod:`geomcheck.fix.verify` applies them to a scratch copy
and checks it again, in rounds, refitting a colliding collision fix clear of the links it hits
(:mod:`geomcheck.fix.clear`); :mod:`geomcheck.fix.offer` gives the verified patches the
service offers.

Below it: what a fix is (:mod:`geomcheck.fixes`: a finding's fix derived from its numbers)
and a fix as text (:mod:`geomcheck.patch`: planned against the sources, applied, diffed).
"""

from __future__ import annotations

from geomcheck.fix.run import FixResult, fix_bundle
from geomcheck.fix.verify import Verified

__all__ = ["FixResult", "Verified", "fix_bundle"]
