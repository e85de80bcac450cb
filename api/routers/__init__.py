"""One router per resource: checks, rules, health."""
