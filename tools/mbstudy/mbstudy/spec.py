"""The study description: a TOML file read into a `Study` (validated, paths resolved)."""

import dataclasses
import hashlib
import pathlib
import string
import tomllib

FIGURES = ("peak", "min", "final", "initial", "mean", "spectrum_peak")


@dataclasses.dataclass
class Study:
    name: str
    path: pathlib.Path  # the TOML file
    fmu: pathlib.Path
    stop_time: float
    step: float
    keep_series: bool
    fixed: dict  # FMU variable -> value, the same in every case
    grid: dict  # variable -> list of values (Cartesian product)
    random: dict  # {"seed": int, "samples": int, "vary": {variable: {dist: [a, b]}}}
    inputs: dict  # input -> [[t, value or variable name], ...] (piecewise constant)
    outputs: dict  # output -> [figure, ...]
    spectrum: dict  # {"start": s, "after_final_of": [...], "settle": s, "band": [f0, f1]}
    derived: dict  # column -> {"ratio": [a, b]}, {"max" | "min" | "mean": [...]}, {"if_else_inf": [c, v]}
    marks: list  # [{"label": str, "where": {variable: value}, ...}]
    plots: list  # [{"kind": "xy" | "histogram" | "sensitivity", ...}]
    sensitivity: dict = dataclasses.field(default_factory=dict)  # {"columns": [...], "resamples", "conf_level", "seed"}
    extremes: dict = dataclasses.field(default_factory=dict)  # {"columns", "quantiles", "most_probable_maximum", ...}
    allowances: dict = dataclasses.field(default_factory=dict)  # column -> {"over" | "below": allowance}
    scene: str = ""  # scene template: resources/scene.toml of every case, `$variable` filled in

    def run_settings(self) -> dict:
        """What every case shares and what changes its results (part of every case id): the
        FMU, the study's settings and the code that runs and reduces a case."""
        code = b"".join((pathlib.Path(__file__).parent / m).read_bytes() for m in ("fmu_run.py", "summary.py"))
        return {
            "fmu_sha256": hashlib.sha256(self.fmu.read_bytes()).hexdigest(),
            "code_sha256": hashlib.sha256(code).hexdigest(),
            "stop_time": self.stop_time,
            "step": self.step,
            "fixed": self.fixed,
            "inputs": self.inputs,
            "outputs": self.outputs,
            "spectrum": self.spectrum,
            "keep_series": self.keep_series,
            "scene": self.scene,
        }


def _need(table, key, where):
    if key not in table:
        raise ValueError(f"{where}: `{key}` is missing")
    return table[key]


def load(path, fmu=None) -> Study:
    """Reads and checks a study file; the FMU path is relative to the file (`fmu`: another
    FMU file instead)."""
    path = pathlib.Path(path).resolve()
    with open(path, "rb") as f:
        d = tomllib.load(f)
    known = {"study", "fixed", "grid", "random", "inputs", "outputs", "spectrum", "derived", "mark", "plot",
             "sensitivity", "extremes", "allowances"}
    unknown = set(d) - known
    if unknown:
        raise ValueError(f"{path}: unknown tables {sorted(unknown)} (known: {sorted(known)})")
    s = _need(d, "study", str(path))
    fmu = pathlib.Path(fmu).resolve() if fmu else (path.parent / _need(s, "fmu", "[study]")).resolve()
    stop, step = float(_need(s, "stop_time", "[study]")), float(_need(s, "step", "[study]"))
    if not (stop > 0 and step > 0 and step <= stop):
        raise ValueError(f"[study]: need 0 < step <= stop_time (got step {step}, stop_time {stop})")
    outputs = d.get("outputs", {})
    if not outputs:
        raise ValueError("[outputs]: name at least one output and its figures")
    for name, figs in outputs.items():
        bad = [f for f in figs if f not in FIGURES]
        if bad:
            raise ValueError(f"[outputs] {name}: unknown figures {bad} (known: {list(FIGURES)})")
    random = d.get("random", {})
    if random:
        _need(random, "seed", "[random]")
        _need(random, "samples", "[random]")
        for name, dist in _need(random, "vary", "[random]").items():
            if len(dist) != 1 or next(iter(dist)) not in ("uniform", "loguniform", "normal"):
                raise ValueError(f"[random.vary] {name}: one of uniform, loguniform, normal = [a, b]")
        _check_design(random)
    grid = d.get("grid", {})
    for name, values in grid.items():
        if not isinstance(values, list) or not values:
            raise ValueError(f"[grid] {name}: a non-empty list of values")
    if grid and d.get("sensitivity"):
        raise ValueError("[sensitivity] needs a study without [grid] (the indices are of the [random] design alone)")
    sensitivity = _sensitivity(d.get("sensitivity", {}), random)
    extremes = {"columns": [], "quantiles": [0.9, 0.95], "most_probable_maximum": True,
                "resamples": 999, "conf_level": 0.95, "seed": 0}
    _known_keys(d.get("extremes", {}), extremes, "[extremes]")
    extremes.update(d.get("extremes", {}))
    allowances = {k: _allowance(k, v) for k, v in d.get("allowances", {}).items()}
    scene = (path.parent / s["scene"]).read_text() if "scene" in s else ""
    _check_scene(scene, set(grid) | set(random.get("vary", {})) if random else set(grid))
    spectrum = {"start": 0.0, "after_final_of": [], "settle": 0.0, "band": [0.0, float("inf")]}
    spectrum.update(d.get("spectrum", {}))
    return Study(
        name=s.get("name", path.stem),
        path=path,
        fmu=fmu,
        stop_time=stop,
        step=step,
        keep_series=bool(s.get("keep_series", False)),
        scene=scene,
        fixed=d.get("fixed", {}),
        grid=grid,
        random=random,
        inputs=d.get("inputs", {}),
        outputs=outputs,
        spectrum=spectrum,
        derived=d.get("derived", {}),
        marks=d.get("mark", []),
        plots=d.get("plot", []),
        sensitivity=sensitivity,
        extremes=extremes,
        allowances=allowances,
    )


def _known_keys(table, defaults, where):
    unknown = sorted(set(table) - set(defaults))
    if unknown:
        raise ValueError(f"{where}: unknown keys {unknown} (known: {sorted(defaults)})")


def _check_scene(scene, varied):
    """A scene template may name only varied variables (`$name`), and only as placeholders."""
    if not scene:
        return
    template = string.Template(scene)
    if not template.is_valid():
        raise ValueError("[study] scene: a dollar sign that is not a placeholder `$name` (write `$$`)")
    unknown = sorted(set(template.get_identifiers()) - varied)
    if unknown:
        raise ValueError(f"[study] scene names {unknown}, which are not [grid] or [random.vary] variables")


def _allowance(column, value):
    """`column = x` (cases over x count) or `column = { below = x }` (cases under x count)."""
    if isinstance(value, dict):
        if set(value) != {"below"}:
            raise ValueError(f"[allowances] {column}: a number (over) or {{ below = number }}")
        return {"below": float(value["below"])}
    return {"over": float(value)}


def _check_design(random):
    from .cases import DESIGNS

    design, n = random.get("design", "monte_carlo"), int(random["samples"])
    if design not in DESIGNS:
        raise ValueError(f"[random] design = {design!r}: one of {list(DESIGNS)}")
    if design in ("sobol", "saltelli") and (n < 2 or n & (n - 1)):
        raise ValueError(f"[random] design = {design!r} needs samples = a power of 2 (got {n})")
    if design == "morris" and any("normal" in dist for dist in random["vary"].values()):
        raise ValueError("[random] design = 'morris' puts points on the ends of each range: "
                         "uniform or loguniform variables only")


def _sensitivity(table, random):
    """[sensitivity]: which columns, and SALib's bootstrap settings; the method follows the
    design (saltelli: Sobol' indices, morris: Morris screening)."""
    if not table:
        return {}
    design = random.get("design", "monte_carlo") if random else None
    if design not in ("saltelli", "morris"):
        raise ValueError("[sensitivity] needs [random] design = 'saltelli' (Sobol' indices) or 'morris'")
    out = {"columns": list(_need(table, "columns", "[sensitivity]")), "resamples": 1000,
           "conf_level": 0.95, "seed": random["seed"]}
    _known_keys(table, out, "[sensitivity]")
    out.update(table)
    out["method"] = "sobol" if design == "saltelli" else "morris"
    return out
