"""What a study's rows answer: sensitivity indices of its design (SALib), characteristic
extremes with bootstrap intervals and the fraction of cases over each allowance (scipy).

Every estimator is a SALib or scipy call; this module only picks the rows and lays out the
results as long tables (one row per figure, with its interval):
- sensitivity: column, method, variable, index (S1, ST for Sobol'; mu, mu_star, sigma for
  Morris), value, conf (half-width of SALib's bootstrap interval at conf_level), low, high;
- extremes: column, statistic (P90, P95, ..., MPM), value, low, high (bootstrap percentile
  interval, scipy.stats.bootstrap), n (finished cases with a value that is not NaN); the
  quantiles are order statistics (numpy's `inverted_cdf`), so +inf values (a deployment that
  never came) count as the largest;
- allowances: column, side ("over" or "below"), allowance, count (cases strictly above, or
  strictly below), n, fraction, low, high (Wilson interval of scipy.stats.binomtest).
The most probable maximum (MPM) is the mode of a Gumbel distribution fitted to the column's
values by maximum likelihood (scipy.stats.gumbel_r.fit: the mode is its location): meaningful
for a column of per-case maxima (a peak, a DAF)."""

import numpy as np
from scipy import stats

from . import cases as cases_mod


def _done_values(rows, column):
    """The column over the finished cases, as floats (failed cases and NaN left out; +inf, a
    time that never came, stays: it is over every allowance and above every finite quantile)."""
    x = np.array([float(r[column]) for r in rows if r["status"] == "done" and r.get(column) is not None],
                 float)
    return x[~np.isnan(x)]


def sensitivity(study, rows) -> list[dict]:
    """SALib's indices of each [sensitivity] column; rows in case order, one per design point.
    A column with a failed case or a non-finite value gets NaN indices and a message."""
    sa = study.sensitivity
    if not sa:
        return []
    problem = cases_mod.problem(study.random)
    out = []
    for column in sa["columns"]:
        y = np.array([float(r[column]) if r["status"] == "done" and r.get(column) is not None else np.nan
                      for r in rows], float)
        if len(y) != len(cases_mod.unit_design(study.random)) or not np.isfinite(y).all():
            bad = int(np.sum(~np.isfinite(y)))
            for name in problem["names"]:
                out.append(dict(column=column, method=sa["method"], variable=name, index="",
                                value=float("nan"), conf=float("nan"), low=float("nan"),
                                high=float("nan"), message=f"{bad} of {len(y)} cases failed or not finite"))
            continue
        if sa["method"] == "sobol":
            from SALib.analyze import sobol

            res = sobol.analyze(problem, y, calc_second_order=bool(study.random.get("second_order", False)),
                                num_resamples=int(sa["resamples"]), conf_level=float(sa["conf_level"]),
                                seed=sa["seed"])
            indices = (("S1", "S1_conf"), ("ST", "ST_conf"))
        else:
            from SALib.analyze import morris

            x = cases_mod.unit_design(study.random)
            res = morris.analyze(problem, x, y, num_resamples=int(sa["resamples"]),
                                 conf_level=float(sa["conf_level"]),
                                 num_levels=int(study.random.get("levels", 4)), seed=sa["seed"])
            indices = (("mu", None), ("mu_star", "mu_star_conf"), ("sigma", None))
        for j, name in enumerate(problem["names"]):
            for key, conf_key in indices:
                v = float(res[key][j])
                c = float(res[conf_key][j]) if conf_key else float("nan")
                out.append(dict(column=column, method=sa["method"], variable=name, index=key, value=v,
                                conf=c, low=v - c, high=v + c, message=""))
    return out


def _quantile_statistic(q):
    def statistic(x, axis=-1):
        # an order statistic (the smallest value with at least q of the cases at or below it):
        # a +inf case counts as the largest value instead of turning an interpolation into NaN
        return np.quantile(x, q, axis=axis, method="inverted_cdf")

    return statistic


def _gumbel_mode(x):
    return stats.gumbel_r.fit(x)[0]


def extremes(study, rows) -> list[dict]:
    """P-quantiles (and the MPM) of each [extremes] column with bootstrap intervals."""
    ex = study.extremes
    out = []
    for column in ex["columns"]:
        x = _done_values(rows, column)
        stats_wanted = [(f"P{round(100 * q):d}", _quantile_statistic(float(q)), True) for q in ex["quantiles"]]
        if ex["most_probable_maximum"]:
            stats_wanted.append(("MPM", _gumbel_mode, False))
        for label, f, vectorized in stats_wanted:
            if len(x) < 2 or (label == "MPM" and not np.isfinite(x).all()):
                out.append(dict(column=column, statistic=label, value=float("nan"), low=float("nan"),
                                high=float("nan"), n=len(x)))
                continue
            with np.errstate(invalid="ignore"):  # its standard error of +inf values is NaN: unused
                res = stats.bootstrap((x,), f, vectorized=vectorized, n_resamples=int(ex["resamples"]),
                                      confidence_level=float(ex["conf_level"]), method="percentile",
                                      rng=np.random.default_rng(ex["seed"]))
            # a bound between two +inf resampled statistics comes back NaN (inf - inf): it is +inf
            low, high = (float(b) if not (np.isnan(b) and np.isinf(x).any()) else float("inf")
                         for b in (res.confidence_interval.low, res.confidence_interval.high))
            out.append(dict(column=column, statistic=label, value=float(f(x)), low=low, high=high, n=len(x)))
    return out


def allowances(study, rows) -> list[dict]:
    """The fraction of finished cases strictly over (or below) each allowance, with its Wilson
    interval."""
    level = float(study.extremes.get("conf_level", 0.95))
    out = []
    for column, limit in study.allowances.items():
        (side, allowance), = limit.items()
        x = _done_values(rows, column)
        k, n = int(np.sum(x > allowance if side == "over" else x < allowance)), len(x)
        if n:
            ci = stats.binomtest(k, n).proportion_ci(confidence_level=level, method="wilson")
            low, high = float(ci.low), float(ci.high)
        else:
            low = high = float("nan")
        out.append(dict(column=column, side=side, allowance=allowance, count=k, n=n,
                        fraction=k / n if n else float("nan"), low=low, high=high))
    return out


def analyse(study, table) -> dict:
    """All three tables of a study's results (a pyarrow table in case order)."""
    rows = table.to_pylist()
    return {"sensitivity": sensitivity(study, rows), "extremes": extremes(study, rows),
            "allowances": allowances(study, rows)}
