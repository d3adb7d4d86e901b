"""Errors with the one-line messages the command line prints (spec cli.md: exit 2 / exit 1)."""


class InputError(ValueError):
    """Bad input: names the file and the field or line at fault (exit status 2)."""

    def __init__(self, path, field, message):
        self.path = str(path)
        self.field = field
        super().__init__(f"{self.path}: {field}: {message}")


class SimulationError(RuntimeError):
    """The solver failed or produced non-finite values (exit status 1)."""
