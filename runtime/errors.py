"""User-facing errors of the runtime.  The CLI prints their message on one line and exits non-zero."""


class RpoError(Exception):
    """Base class: an error the user can fix (bad input, missing tool, stale build)."""


class ModelError(RpoError):
    """The generated model is missing, stale, or cannot be compiled or loaded."""


class ScenarioError(RpoError):
    """A scenario file is invalid; the message names the field and the allowed range."""


class OutputError(RpoError):
    """The output folder cannot be written (exists already, not writable)."""


class CampaignError(RpoError):
    """A campaign file, folder or option is invalid; the message names the key and the allowed range."""
