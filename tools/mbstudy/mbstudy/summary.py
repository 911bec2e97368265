"""Summary figures of one output's time series, and derived columns of a result row."""

import numpy as np

# Zero padding of the spectrum: the frequency grid is 1 / (PAD * window length).
PAD = 64


def spectrum_peak(t, x, band):
    """Frequency [Hz] of the largest amplitude of the mean-removed, Hann-windowed signal `x`
    (uniform steps `t`) inside `band`, from a zero-padded real FFT; NaN if fewer than 8 samples
    or no peak. The window keeps the truncation of a decaying signal from raising false peaks."""
    if len(x) < 8:
        return float("nan")
    dt = (t[-1] - t[0]) / (len(t) - 1)
    n = PAD * len(x)
    amp = np.abs(np.fft.rfft(np.hanning(len(x)) * (x - np.mean(x)), n))
    f = np.fft.rfftfreq(n, dt)
    inside = (f >= band[0]) & (f <= band[1])
    if not inside.any() or not np.isfinite(amp[inside]).all() or amp[inside].max() <= 0.0:
        return float("nan")
    return float(f[inside][np.argmax(amp[inside])])


def spectrum_window_start(spec, finals):
    """Start time of the spectral window: a fixed start, or `settle` after the latest final
    value of the named outputs (e.g. the lock times); NaN if one of them is NaN."""
    start = float(spec["start"])
    if spec["after_final_of"]:
        last = [float(finals[name]) for name in spec["after_final_of"]]
        start = float("nan") if any(np.isnan(last)) else max(last) + float(spec["settle"])
    return start


def figures(name, wanted, t, x, window_start, band):
    out = {}
    for fig in wanted:
        if fig == "peak":
            v = np.max(x)
        elif fig == "min":
            v = np.min(x)
        elif fig == "final":
            v = x[-1]
        elif fig == "initial":
            v = x[0]
        elif fig == "mean":
            v = np.mean(x)
        else:  # spectrum_peak
            inside = t >= window_start if np.isfinite(window_start) else np.zeros(len(t), bool)
            v = spectrum_peak(t[inside], x[inside], band)
        out[f"{name}.{fig}"] = float(v)
    return out


def derived(spec, row):
    """Columns computed from a row's figures and the derived columns above them: {"ratio":
    [a, b]} is a / b, {"max": [...]} the largest, {"min": [...]} the smallest, {"mean": [...]} the
    mean of the named columns, {"if_else_inf": [c, v]} v where c is not 0 and +inf elsewhere
    (a deployment time that never came)."""
    out = {}
    for name, d in spec.items():
        (kind, cols), = d.items()
        have = {**row, **out}
        if kind == "ratio":
            out[name] = have[cols[0]] / have[cols[1]] if have[cols[1]] != 0 else float("nan")
        elif kind == "max":
            out[name] = max(have[c] for c in cols)
        elif kind == "min":
            out[name] = min(have[c] for c in cols)
        elif kind == "mean":
            out[name] = float(np.mean([have[c] for c in cols]))
        elif kind == "if_else_inf":  # [condition, value]: value where condition != 0, else +inf
            out[name] = float(have[cols[1]]) if have[cols[0]] != 0 else float("inf")
        else:
            raise ValueError(f"[derived] {name}: unknown kind {kind} (ratio, max, min, mean, if_else_inf)")
    return out
