"""The errors a command reports to its user (the CLI maps them to exit statuses)."""

from __future__ import annotations


class UsageError(Exception):
    """Bad input that is not about a deck's contents (an option, a path): exit status 2."""


class RunFailed(UsageError):
    """The program (emulated or core) could not run to its end: exit status 3."""
