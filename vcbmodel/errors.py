"""Errors with the one-line messages the command line prints (spec cli.md: exit 2 / exit 1)."""


class InputError(ValueError):
    """Bad input: names the file and the field or line at fault (exit status 2)."""

    def __init__(self, path, field, message):
        self.path = str(path)
        self.field = field
        self.message = message
        super().__init__(f"{self.path}: {field}: {message}")

    def __reduce__(self):
        """Pickled with its three parts: an InputError raised in a worker process reaches the command
        line as itself (one line, status 2), not as a broken process pool."""
        return (InputError, (self.path, self.field, self.message))


class ImpossibleValue(InputError):
    """A rig value beyond what any mechanism has (a unit slip: grams typed as kg), refused naming the slip
    (:func:`vcbmodel.rig.plausibility.plausibility`)."""

    def __reduce__(self):
        return (ImpossibleValue, (self.path, self.field, self.message))


class SimulationError(RuntimeError):
    """The solver failed or produced non-finite values (exit status 1)."""
