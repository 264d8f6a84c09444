"""The two errors a user meets: bad input, which names the key, the value and what is allowed
(every error at once where several are found; tisph.settings.config re-exports it), and a run that
went unstable, which says when, what, where and a likely cause. Without Taichi: they sit below
everything that raises them (the settings, the engine's hooks, the bed coupling, the runner)."""


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


class SimulationError(RuntimeError):
    """The run went unstable; the message says where, what and a likely cause."""


def unstable(solver, what, where, cause):
    """The SimulationError message of every instability: when, what went wrong, where, a likely cause."""
    return f"unstable at step {solver.steps}, t = {solver.time:.6g} s: {what}; {where}. Likely cause: {cause}."
