"""Errors of the core. User errors subclass :class:`MotoflexError`; the CLI prints them without a
traceback and exits non-zero.
"""

__all__ = ["MotoflexError", "ConfigError", "ModelError", "ProtocolError"]


class MotoflexError(Exception):
    """A problem the user can fix (bad input, missing file); printed without a traceback."""


class ConfigError(MotoflexError, ValueError):
    """A configuration value is missing, unknown, of the wrong type or out of range.

    The message always names the file, the key (dotted path) and what is allowed.
    """

    def __init__(self, source, key, problem):
        self.source = str(source)
        self.key = key
        self.problem = problem
        where = f"{self.source}: key '{key}'" if key else self.source
        super().__init__(f"{where}: {problem}")


class ModelError(MotoflexError, ValueError):
    """A model is inconsistent (e.g. joint points that do not meet, a singular structure)."""


class ProtocolError(MotoflexError, ValueError):
    """A bench protocol cannot be run as described (e.g. too fast for the sensor)."""
