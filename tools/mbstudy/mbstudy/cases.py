"""The cases of a study: the Cartesian product of its grid, times its seeded random samples.

The samples come from the `[random]` design: `monte_carlo` (independent draws, numpy), `lhs`
(Latin hypercube, scipy.stats.qmc), `sobol` (a scrambled Sobol' sequence, scipy.stats.qmc),
`saltelli` (SALib's Sobol'-index design, N (D + 2) points) or `morris` (SALib's Morris
trajectories, r (D + 1) points). The last four draw points in the unit hypercube, mapped to
each variable's distribution by its inverse CDF (`unit_design` gives them back for the
sensitivity analysis).

A case is a dict of the varied variables (FMU parameters or schedule variables) with an index
and an id: a hash of the study's run settings and the case's values, so that a resumed study
knows which cases are finished and a changed study (other FMU, stop time, ...) runs again."""

import dataclasses
import hashlib
import itertools
import json

import numpy as np

DESIGNS = ("monte_carlo", "lhs", "sobol", "saltelli", "morris")


@dataclasses.dataclass(frozen=True)
class Case:
    index: int
    id: str
    values: dict
    mark: str  # label of the study's [[mark]] this case matches, or ""


def _draw(rng, dist, n):
    (kind, (a, b)), = dist.items()
    if kind == "uniform":
        return rng.uniform(a, b, n)
    if kind == "loguniform":
        return np.exp(rng.uniform(np.log(a), np.log(b), n))
    return rng.normal(a, b, n)  # normal = [mean, standard deviation]


def problem(random):
    """SALib's problem of a `[random]` table: its variables on the unit interval."""
    names = list(random["vary"])
    return {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}


def unit_design(random) -> np.ndarray:
    """The design's points in the unit hypercube (rows in case order) for the designs that
    have them (all but monte_carlo)."""
    from scipy.stats import qmc

    kind, n, seed = random.get("design", "monte_carlo"), int(random["samples"]), random["seed"]
    d = len(random["vary"])
    if kind == "lhs":
        return qmc.LatinHypercube(d, rng=np.random.default_rng(seed)).random(n)
    if kind == "sobol":
        return qmc.Sobol(d, scramble=True, rng=np.random.default_rng(seed)).random_base2(int(np.log2(n)))
    if kind == "saltelli":
        from SALib.sample import sobol

        return sobol.sample(problem(random), n, calc_second_order=bool(random.get("second_order", False)),
                            seed=seed)
    if kind == "morris":
        from SALib.sample import morris

        return morris.sample(problem(random), n, num_levels=int(random.get("levels", 4)), seed=seed)
    raise ValueError(f"[random] design {kind!r} has no unit-hypercube points")


def _from_unit(dist, u):
    """Inverse CDF of a variable's distribution at unit values `u`."""
    from scipy import stats

    (kind, (a, b)), = dist.items()
    if kind == "uniform":
        return stats.uniform.ppf(u, loc=a, scale=b - a)
    if kind == "loguniform":
        return stats.loguniform.ppf(u, a, b)
    return stats.norm.ppf(u, loc=a, scale=b)


def samples(random) -> list[dict]:
    """The design's points as {variable: value} dicts, in case order."""
    if random.get("design", "monte_carlo") == "monte_carlo":
        rng = np.random.default_rng(random["seed"])
        n = int(random["samples"])
        draws = {k: _draw(rng, dist, n) for k, dist in random["vary"].items()}
    else:
        u = unit_design(random)
        draws = {k: _from_unit(dist, u[:, j]) for j, (k, dist) in enumerate(random["vary"].items())}
        n = len(u)
    return [{k: float(draws[k][i]) for k in draws} for i in range(n)]


def _plain(v):
    """A TOML or numpy value as a plain Python bool, int, float or str."""
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        return float(v)
    return v


def case_id(settings: dict, values: dict) -> str:
    text = json.dumps({"run": settings, "case": values}, sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _mark(study, values):
    for m in study.marks:
        if all(values.get(k) == v for k, v in m["where"].items()):
            return m["label"]
    return ""


def generate(study) -> list[Case]:
    names = list(study.grid)
    points = [dict(zip(names, map(_plain, p))) for p in itertools.product(*study.grid.values())]
    drawn = samples(study.random) if study.random else [{}]
    settings = study.run_settings()
    cases = []
    for p in points:
        for s in drawn:
            values = {**p, **s}
            cases.append(Case(len(cases), case_id(settings, values), values, _mark(study, values)))
    return cases
