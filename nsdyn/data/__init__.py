"""Bundled data: frame definitions (``frames``) and synthetic ground motions (``records``)."""
