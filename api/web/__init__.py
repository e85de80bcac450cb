"""The web page of the service: templates, static files and the helpers that feed them."""

__all__ = ["forms"]
