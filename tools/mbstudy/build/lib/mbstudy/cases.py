"""The cases of a study: the Cartesian product of its grid, times its seeded random samples.

A case is a dict of the varied variables (FMU parameters or schedule variables) with an index
and an id: a hash of the study's run settings and the case's values, so that a resumed study
knows which cases are finished and a changed study (other FMU, stop time, ...) runs again."""

import dataclasses
import hashlib
import itertools
import json

import numpy as np


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
    if study.random:
        rng = np.random.default_rng(study.random["seed"])
        n = int(study.random["samples"])
        draws = {k: _draw(rng, dist, n) for k, dist in study.random["vary"].items()}
        samples = [{k: float(draws[k][i]) for k in draws} for i in range(n)]
    else:
        samples = [{}]
    settings = study.run_settings()
    cases = []
    for p in points:
        for s in samples:
            values = {**p, **s}
            cases.append(Case(len(cases), case_id(settings, values), values, _mark(study, values)))
    return cases
