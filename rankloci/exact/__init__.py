"""Exact cross-checks by external computer algebra (Singular)."""
