"""Bad input: the error that names the key, the value and what is allowed (every error at once
where several are found). tisph.settings.config re-exports it; it sits below everything that raises it."""


class ConfigError(ValueError):
    """Bad input: names the field, the value, and what is allowed."""

    def __init__(self, field, value, allowed, hint=""):
        self.field, self.value, self.allowed = field, value, allowed
        msg = f"config error: {field} = {value!r} is not allowed; expected {allowed}"
        if hint:
            msg += f" ({hint})"
        super().__init__(msg)


class ConfigErrors(ConfigError):
    """Several bad inputs at once, one line each; field, value and allowed are the first's."""

    def __init__(self, errors):
        self.errors = list(errors)
        first = self.errors[0]
        self.field, self.value, self.allowed = first.field, first.value, first.allowed
        ValueError.__init__(self, "\n".join(str(e) for e in self.errors))


def raise_collected(errors):
    """Raise what was collected: one error as itself, several together."""
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise ConfigErrors(errors)
