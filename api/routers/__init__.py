"""One router per resource: checks, rules, health and the web page."""

__all__ = ["checks", "health", "rules", "web"]
