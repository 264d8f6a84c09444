"""An ensemble: one case run with several random seeds (the initial bed's), each metric as its
mean, standard deviation and standard error over the runs, the scatter a chaotic metric carries
(a ripple count, a ripple length, a scour depth) that one run hides."""

import math


def _finite(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def spread(values):
    """The finite values' n, mean, sample standard deviation (n - 1) and standard error of the
    mean; std and stderr are None under two values. `values` is kept as given (None: no value)."""
    v = [float(x) for x in values if _finite(x)]
    n = len(v)
    mean = sum(v) / n if n else None
    std = math.sqrt(sum((x - mean) ** 2 for x in v) / (n - 1)) if n >= 2 else None
    return {
        "values": [float(x) if _finite(x) else None for x in values],
        "n": n,
        "mean": mean,
        "std": std,
        "stderr": std / math.sqrt(n) if std is not None else None,
    }


def ensemble_metrics(metric_dicts):
    """{metric: spread} over the runs' metrics (summary.json's `metrics`, None for a run that gave
    none): every metric that is a number in at least one run, in the first run's order."""
    names = []
    for m in metric_dicts:
        for k, v in (m or {}).items():
            if _finite(v) and k not in names:
                names.append(k)
    return {k: spread([(m or {}).get(k) for m in metric_dicts]) for k in names}
