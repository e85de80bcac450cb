"""``GET /v1/rules``: the rule registry, with each rule's documentation."""

from __future__ import annotations

from fastapi import APIRouter, Depends, HTTPException

from api.http.auth import require_token
from api.http.schemas import ErrorOut, RuleOut
from geomcheck.errors import UsageError
from geomcheck.rules import FAMILY_TITLES, Rule, all_rules, get_rule

router = APIRouter(prefix="/v1/rules", tags=["rules"], dependencies=[Depends(require_token)])


def rule_out(rule: Rule) -> RuleOut:
    return RuleOut(
        code=rule.code,
        name=rule.name,
        severity=rule.severity.value,
        family=rule.family,
        family_title=FAMILY_TITLES.get(rule.family, ""),
        summary=rule.summary,
        what=rule.what,
        why=rule.why,
        example=rule.example,
        fix=rule.fix,
    )


@router.get("", response_model=list[RuleOut], summary="Every rule, by code")
def list_rules() -> list[RuleOut]:
    return [rule_out(r) for r in all_rules()]


@router.get(
    "/{code}",
    response_model=RuleOut,
    summary="One rule by code (GC301) or name",
    responses={404: {"model": ErrorOut, "description": "no such rule"}},
)
def read_rule(code: str) -> RuleOut:
    try:
        return rule_out(get_rule(code))
    except UsageError as err:
        raise HTTPException(404, str(err)) from None
