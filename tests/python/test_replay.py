"""`mbcosim simulate --replay` (issue #23, docs/replay.md): the 3D replay page of a PanelLock and a
RopeBlock run, loaded in headless Chromium (apt `chromium`, installed by tests/setup_env.sh).

Checked independently of one another:
(a) a screenshot of the page shows a scene (enough pixels that are not the background);
(b) screenshots at two times (URL hash `#t=...`) differ visibly, and the page's time display
    shows the time asked for;
(c) the frames embedded in the page hold the bodies where the CSV written by the same run puts
    them: PanelLock hinge angles from the panel boxes' orientations, RopeBlock block pose, hook
    position and contact count, at every output time.
Drives the built binary (MBCOSIM_BIN, as test_cli.py); needs no FMU.
"""

import csv
import json
import math
import os
import pathlib
import re
import shutil
import struct
import subprocess
import zlib

import numpy as np
import pytest
from conftest import ROOT

EXE = os.environ.get("MBCOSIM_BIN", str(ROOT / "target" / "release" / "mbcosim"))
WIDTH, HEIGHT = 800, 600
BAR = 44  # height of the page's control bar [px]
BACKGROUND = (0xEE, 0xF1, 0xF5)  # scene background of viewer.js

LOCK = {"root": math.pi / 2, "panel": math.pi}
N_PANELS = 3


def simulate(out_dir, model, *args):
    assert pathlib.Path(EXE).exists(), f"{EXE} is missing: build it (cargo build --release --bin mbcosim)"
    csv_path, html = out_dir / f"{model}.csv", out_dir / f"{model}.html"
    r = subprocess.run([EXE, "simulate", model, *map(str, args), "--header", "names", "--out", csv_path,
                        "--replay", html, "--timing"], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {"csv": rows, "html": html, "stderr": r.stderr}


@pytest.fixture(scope="module")
def panel_lock(tmp_path_factory):
    # 8 s: the root hinge and the panels well on their way out (root about 1.55 rad)
    return simulate(tmp_path_factory.mktemp("replay_panel"), "PanelLock", "--stop", 8, "--step", 0.1,
                    "--set", f"n_panels={N_PANELS}", "--set", f"root_lock_angle={LOCK['root']}",
                    "--set", f"panel_lock_angle={LOCK['panel']}",
                    "--outputs", ",".join(f"hinge{k}_angle" for k in range(N_PANELS + 1)))


@pytest.fixture(scope="module")
def rope_block(tmp_path_factory):
    # the hook hoists at 1 m/s (reached over 0.5 s): the block rises about 1.7 m in 2 s
    return simulate(tmp_path_factory.mktemp("replay_rope"), "RopeBlock", "--stop", 2, "--step", 0.05,
                    "--set", "segments=20", "--set", "hook0_vz=1.0",
                    "--outputs", "hook0_x,hook0_y,hook0_z,block_x,block_y,block_z,block_qw,block_qx,block_qy,"
                                 "block_qz,contact_count")


# --- the page as a browser shows it ---------------------------------------------------------

def chromium():
    exe = shutil.which("chromium")
    if exe is None:
        pytest.fail("chromium is missing: tests/setup_env.sh installs it (apt-get install chromium)")
    return exe


def browse(html, t, tmp, *mode, budget_ms=8000):
    """Runs headless Chromium on `html#t=<t>` (`html` alone for t None) with software WebGL for
    `budget_ms` of virtual time; `mode`: --screenshot=... or --dump-dom. Returns the completed
    process."""
    profile = tmp / "chromium-profile"
    profile.mkdir(exist_ok=True)
    cmd = [chromium(), "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
           "--hide-scrollbars", "--no-first-run", f"--user-data-dir={profile}",
           f"--window-size={WIDTH},{HEIGHT}", f"--virtual-time-budget={budget_ms}", *mode,
           html.resolve().as_uri() + ("" if t is None else f"#t={t}")]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=180)
    assert r.returncode == 0, r.stderr[-2000:]
    return r


def read_png(path):
    """RGB pixels of an 8-bit, non-interlaced PNG (what Chromium writes) as an array
    (height, width, 3)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat = 8, b""
    while pos < len(data):
        (length,), kind = struct.unpack(">I", data[pos:pos + 4]), data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            w, h, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and interlace == 0 and color in (2, 6), (depth, color, interlace)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    bpp = 3 if color == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    img = np.zeros((h, stride), dtype=np.uint8)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1).astype(np.int32)
        if f == 0:
            cur = line
        elif f == 2:
            cur = (line + prev) & 0xFF
        else:  # 1 sub, 3 average, 4 Paeth: left-dependent, byte by byte
            cur = np.zeros(stride, dtype=np.int32)
            for x in range(stride):
                a = cur[x - bpp] if x >= bpp else 0
                b = prev[x]
                c = prev[x - bpp] if x >= bpp else 0
                if f == 1:
                    pred = a
                elif f == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (line[x] + pred) & 0xFF
        img[y] = cur
        prev = cur
    return img.reshape(h, w, bpp)[:, :, :3]


def screenshot(run, t, tmp):
    png = tmp / f"{run['html'].stem}_t{t}.png"
    browse(run["html"], t, tmp, f"--screenshot={png}")
    img = read_png(png)
    assert img.shape[:2] == (HEIGHT, WIDTH), img.shape
    # the 3D view only: below the title line, above the control bar
    return img[30:HEIGHT - BAR]


def scene_pixels(view):
    """Share of the view's pixels that are not the background."""
    diff = np.abs(view.astype(np.int32) - np.array(BACKGROUND)).max(axis=2)
    return float((diff > 24).mean())


def changed_pixels(a, b):
    return float((np.abs(a.astype(np.int32) - b.astype(np.int32)).max(axis=2) > 24).mean())


def shown_time(run, t, tmp):
    dom = browse(run["html"], t, tmp, "--dump-dom").stdout
    assert 'data-ready="1"' in dom, dom[-3000:]
    m = re.search(r'<span id="time">t = ([0-9.]+) s', dom)
    assert m, dom[-3000:]
    return float(m.group(1))


@pytest.mark.parametrize("model,times", [("panel_lock", (0.5, 7.5)), ("rope_block", (0.0, 2.0))])
def test_screenshots_show_the_scene_moving(model, times, request, tmp_path):
    run = request.getfixturevalue(model)
    a, b = (screenshot(run, t, tmp_path) for t in times)
    for t, view in zip(times, (a, b)):
        share = scene_pixels(view)
        assert share > 0.03, f"{model} at t = {t} s: only {share:.2%} of the view is not background"
    moved = changed_pixels(a, b)
    assert moved > 0.005, f"{model}: t = {times[0]} s and {times[1]} s differ in {moved:.2%} of the pixels only"
    for t in times:
        assert shown_time(run, t, tmp_path) == pytest.approx(t, abs=1e-9)


def test_the_page_plays_from_the_start_without_a_time(panel_lock, tmp_path):
    # headless Chromium's virtual time with software WebGL once (CI, 2026-11-29) dumped the page
    # before its first animation frame (t = 0.000 s after 6 s of virtual time); a second look
    # with twice the budget tells a slow first frame from a page that does not play
    for budget_ms in (6000, 12000):
        dom = browse(panel_lock["html"], None, tmp_path, "--dump-dom", budget_ms=budget_ms).stdout
        m = re.search(r'<span id="time">t = ([0-9.]+) s / ([0-9.]+) s', dom)
        assert m, dom[-3000:]
        if float(m.group(1)) > 0.0:
            break
    assert 0.0 < float(m.group(1)) < float(m.group(2)), m.group(0)
    assert '<button id="play" type="button">Pause</button>' in dom


# --- the frames in the page against the CSV -------------------------------------------------

def frames_of(run):
    html = run["html"].read_text()
    assert not re.search(r"<script[^>]*\ssrc=|<link[^>]*\shref=", html), "the page loads something"
    m = re.search(r'<script type="application/json" id="replay-data">(.*?)</script>', html, re.S)
    assert m, "no replay data in the page"
    data = json.loads(m.group(1))
    assert data["format"] == 1
    return data


def paired(run):
    """(CSV row, frame) for every CSV row; the frames are the same output points."""
    data = frames_of(run)
    frames = data["frames"]
    assert len(frames) == len(run["csv"])
    for row, f in zip(run["csv"], frames):
        assert f["t"] == pytest.approx(float(row["time"]), abs=1e-12)
        yield row, f


def yaw(p):
    """Yaw [rad] of a shape's x axis about world z, from its pose [x, y, z, qw, qx, qy, qz]."""
    w, x, y, z = p[3:7]
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def test_panel_boxes_turn_by_the_hinge_angles(panel_lock):
    data = frames_of(panel_lock)
    plates = ["yoke"] + [f"panel{k}" for k in range(1, N_PANELS + 1)]
    names = {"satellite", *plates, *(f"hinge{k}" for k in range(N_PANELS + 1))}
    assert set(data["roles"]) == names
    assert data["roles"]["panel1"] == "panel" and data["roles"]["hinge0"] == "hinge"
    worst = 0.0
    for row, f in paired(panel_lock):
        previous = yaw(f["s"]["satellite"]["p"])
        for k, plate in enumerate(plates):
            # build.rs: hinge k's frames have z = s_k e_z, s = +1, -1, +1, ...; theta = lock + s dyaw
            s = -1.0 if k % 2 == 1 else 1.0
            lock = LOCK["root"] if k == 0 else LOCK["panel"]
            now = yaw(f["s"][plate]["p"])
            theta = lock + s * wrap(now - previous)
            worst = max(worst, abs(theta - float(row[f"hinge{k}_angle"])))
            previous = now
    assert worst < 1e-6, f"hinge angle from the page's boxes off the CSV by {worst} rad"
    # the root hinge has opened by more than a radian: the frames hold a deployment
    first, last = panel_lock["csv"][0], panel_lock["csv"][-1]
    assert float(last["hinge0_angle"]) - float(first["hinge0_angle"]) > 1.0


def test_block_and_hook_poses_equal_the_outputs(rope_block):
    data = frames_of(rope_block)
    assert {"block", "hook0", "contact_nodes", "sling0", "sling3"} <= set(data["roles"])
    contacts_geometry = None
    for row, f in paired(rope_block):
        block = f["s"]["block"]
        assert block["p"] == [float(row[c]) for c in
                              ("block_x", "block_y", "block_z", "block_qw", "block_qx", "block_qy", "block_qz")]
        assert f["s"]["hook0"]["p"][:3] == [float(row[c]) for c in ("hook0_x", "hook0_y", "hook0_z")]
        contacts = f["s"]["contact_nodes"]
        if "g" in contacts:
            contacts_geometry = contacts["g"]
        assert len(contacts_geometry["points"]) == 3 * int(row["contact_count"])
        sling = f["s"]["sling0"]["g"]  # rope points move every frame: written every frame
        assert sling["kind"] == "polyline" and len(sling["points"]) >= 6
    rise = float(rope_block["csv"][-1]["block_z"]) - float(rope_block["csv"][0]["block_z"])
    assert rise > 1.0, f"the block rose {rise} m only"


def test_timing_reports_the_snapshot_cost(rope_block):
    m = re.search(r"timing: replay ([0-9.e-]+) s for (\d+) snapshots .* page (\d+) bytes", rope_block["stderr"])
    assert m, rope_block["stderr"]
    assert int(m.group(2)) == len(rope_block["csv"])
    assert int(m.group(3)) == rope_block["html"].stat().st_size


def test_a_model_without_a_scene_is_refused(tmp_path):
    r = subprocess.run([EXE, "simulate", "PidController", "--stop", "0.1", "--out", tmp_path / "p.csv",
                        "--replay", tmp_path / "p.html"], capture_output=True, text=True, timeout=60)
    assert r.returncode != 0
    assert "has no 3D scene" in r.stderr and "panicked" not in r.stderr, r.stderr
    assert not (tmp_path / "p.html").exists()
