"""The parameter study: the scenes' decks, the CSV's rows and columns, the Markdown tables."""

from __future__ import annotations

import csv
import hashlib
import io
import math
from pathlib import Path

import pytest

from deck_emulator.studies import sweep
from deck_emulator.legacy.deck import read_deck
from deck_emulator.studies.report_tables import REPORT

ROOT = Path(__file__).resolve().parents[2]


def test_grid_parsing():
    assert sweep.parse_grid("20,40") == [20.0, 40.0]
    assert sweep.parse_grid("0:45:5") == [float(a) for a in range(0, 50, 5)]
    assert sweep.parse_grid("10,20:40:10, 10") == [10.0, 20.0, 30.0, 40.0]
    for bad in ("", "1:2", "0:10:0", "x"):
        with pytest.raises(ValueError):
            sweep.parse_grid(bad)


def test_speed_and_angle_are_punched_as_the_report_decks_are():
    assert sweep.vvb_for(40) == -58.66  # the report's deck: 58.667 cut to two decimals
    assert sweep.vvb_for(20) == -29.33
    assert sweep.vvb_for(10) == -14.66
    assert sweep.vvb_for(40, decimals=5) == -58.66666
    assert sweep.alpha_for(15) == 0.2618 and sweep.alpha_for(30) == 0.5236


@pytest.mark.parametrize("name", sorted(REPORT))
def test_the_report_cases_are_exactly_the_decks(name):
    speed, angle = {
        "steel40": (40, 0),
        "steel40_a15": (40, 15),
        "steel40_a30": (40, 30),
        "steel20": (20, 0),
        "steel20_a15": (20, 15),
        "steel20_a30": (20, 30),
    }[name]
    base = read_deck(ROOT / "decks" / "steel40.dat")
    assert sweep.scene_name(speed, angle) == name
    assert (
        sweep.scene_deck(base, speed, angle).values
        == read_deck(ROOT / "decks" / f"{name}.dat").values
    )


def _parser():
    from deck_emulator.cli import build_parser

    parser = build_parser()
    return parser


@pytest.fixture(scope="module")
def small_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep")
    args = _parser().parse_args(
        [
            "sweep",
            "--post",
            "steel",
            "--speeds",
            "30,40",
            "--angles",
            "0,15",
            "--jobs",
            "2",
            "--erratum",
            "ed-direction",
            "--out",
            str(out),
        ]
    )
    assert args.func(args) == 0
    return out


def test_csv_has_a_row_per_scene_and_every_column(small_sweep):
    text = (small_sweep / "sweep.csv").read_text()
    rows = list(csv.DictReader(io.StringIO(text)))
    assert len(rows) == 4
    assert tuple(rows[0].keys()) == sweep.COLUMNS
    assert [(float(r["speed_mph"]), float(r["angle_deg"])) for r in rows] == [
        (30, 0),
        (30, 15),
        (40, 0),
        (40, 15),
    ]
    for col in (
        "hit",
        "delta_v_crush_mph",
        "delta_v_contact_mph",
        "max_decel_g",
        "XPL",
        "ZQL",
        "hit_time_s",
        "hit_surface",
        "report_time_to_hit_ground_ms",
        "oiv_m_s",
        "ora_g",
        "body_clearance_ft",
        "roof_clearance_ft",
        "errata",
        "report_XPL",
        "diff_XPL",
    ):
        assert col in rows[0]
    # each quantity once, in one unit: the hit's time in s (the report's own rows keep ms)
    assert "time_to_hit_ground_ms" not in rows[0] and "time_to_hit_car_ms" not in rows[0]
    for r in rows:
        assert r["engine"] == "emulator" and r["error"] == ""
        assert r["hit"].startswith("hit ")
        assert float(r["VVB_ft_s"]) == sweep.vvb_for(float(r["speed_mph"]))
        assert math.isclose(float(r["ALPHA_rad"]), sweep.alpha_for(float(r["angle_deg"])))
        # the erratum as requested on the command line, for every scene
        assert r["errata"] == "ed-direction"
        assert "errata: ed-direction" in r["settings"]
        assert 0 < float(r["oiv_m_s"]) < 3.0
    by = {r["scene"]: r for r in rows}
    # the report has 40 mph / 0 and 15 degrees, not 30 mph
    assert by["steel40"]["report_XQL"] == repr(REPORT["steel40"]["XQL"])
    d = float(by["steel40"]["XQL"]) - REPORT["steel40"]["XQL"]
    assert float(by["steel40"]["diff_XQL"]) == pytest.approx(d)
    assert by["steel40_a15"]["report_time_to_hit_ground_ms"] != ""
    assert all(by["steel30"][c] == "" for c in by["steel30"] if c.startswith(("report_", "diff_")))


def test_markdown_is_laid_out_like_tables_11_and_12(small_sweep):
    md = (small_sweep / "sweep.md").read_text()
    assert "## 30 mph" in md and "## 40 mph" in md
    assert "| APPROACH ANGLE α (DEG) | 0 | 15 |" in md
    for label in (
        "DECREASE IN VEHICLE VELOCITY (MPH)",
        "MAXIMUM VEHICLE DECELERATION",
        "XPL (FT)",
        "ZQL (FT)",
        "TIME TO HIT CAR (MILLISEC)",
        "TIME TO HIT GROUND (MILLISEC)",
        "COMMENTS",
        "OIV m/s",
        "ORA g",
        "least clearance over roof/windshield",
        "post's line first inside the car outline",
    ):
        assert label in md
    # 40 mph, 0 degrees: "ours (report, diff)"
    row = next(l for l in md.splitlines() if l.startswith("| XQL (FT)") and "(-40.60" in l)
    assert "(-40.60, " in row
    assert "ed-direction¹" in md and "¹ errata applied as requested" in md


def test_core_engine_row(tmp_path):
    rows = sweep.sweep([40], [0], engine="core", jobs=1, quiet=True)
    (r,) = rows
    assert r["engine"] == "core" and r["error"] == ""
    assert r["hit"] == "hit ground (R)" and r["comment"] == "POST HITS GROUND WITH POINT R"
    assert r["report_XQL"] == REPORT["steel40"]["XQL"]
    assert abs(r["diff_XQL"]) < 1.0
    # the report's ΔV (crush-pulse end) is the smaller of the two: the car slows on after it
    assert 0 < r["delta_v_crush_mph"] < r["delta_v_contact_mph"]


def test_angled_scene_as_printed_stops_and_names_the_erratum():
    (r,) = sweep.sweep([40], [15], engine="emulator", jobs=1, quiet=True)
    assert r["errata"] == "none" and r["hit"] == ""
    assert "ED" in r["error"]


def test_bad_grid_is_refused_before_any_run(tmp_path):
    from deck_emulator.errors import UsageError as CLIError

    from deck_emulator.app import call

    with pytest.raises(CLIError):  # the command's function refuses it, before any run
        call("sweep", speeds="0,40", angles="0", out=str(tmp_path / "x"))
    assert not (tmp_path / "x").exists()


def test_a_batch_of_scenes_gives_the_rows_of_its_scenes_one_by_one():
    """The worker's batch (the core's scenes through CoreEngine.run_batch, the emulator's one
    after another) gives each scene the row it gets alone; only the run times differ."""
    base = str(ROOT / "decks" / "steel40.dat")
    jobs = [dict(base=base, speed=float(s), angle=float(a), engine=e, options=o, post="steel",
                 vvb_decimals=2)
            for s, a, e, o in ((40, 0, "core", {"preset": "legacy"}),
                               (20, 15, "emulator", {"errata": ["ed-direction"]}),
                               (30, 15, "core", {"preset": "legacy"}),
                               (40, 30, "core", {"preset": "physical"}))]
    together = sweep._scene_rows(jobs)
    alone = [sweep._scene_rows([j])[0] for j in jobs]
    assert [r["engine"] for r in together] == ["core", "emulator", "core", "core"]
    assert all(r["error"] == "" and r["hit"] for r in together)
    for a, b in zip(together, alone):
        a, b = dict(a), dict(b)
        assert a.pop("run_s") > 0 and b.pop("run_s") > 0
        assert a == b


def test_a_batch_given_its_base_deck_reads_no_deck_file(monkeypatch):
    """The command reads the base deck once and hands it with each batch: a worker's batch
    then reads no deck file of its own, and its rows are those of a batch that read it."""
    base = str(ROOT / "decks" / "steel40.dat")
    jobs = [dict(base=base, speed=float(s), angle=0.0, engine="core",
                 options={"preset": "legacy"}, post="car", vvb_decimals=2) for s in (25, 35)]
    read = sweep._scene_rows(jobs)
    given = {base: read_deck(base)}
    monkeypatch.setattr(sweep, "read_deck", lambda path: pytest.fail(f"{path} read again"))
    handed = sweep._scene_rows(jobs, given)
    for a, b in zip(read, handed):
        a, b = dict(a), dict(b)
        assert a.pop("run_s") > 0 and b.pop("run_s") > 0
        assert a == b


def test_a_base_deck_names_the_scenes_and_the_page(tmp_path, capsys):
    """A sweep of another deck is named after it, not after the report's post: the page's
    "Base deck" line and the scenes (car820.dat -> car820_v21.75)."""
    from deck_emulator.cli import main

    deck = tmp_path / "car820.dat"
    from deck_emulator.engine.assemblies import to_deck_text

    # steel40 with a car 10 % heavier: a deck of the user's, not one of the report's
    values = dict(read_deck(ROOT / "decks" / "steel40.dat").values)
    values["WV"] *= 1.1
    deck.write_text(to_deck_text(values))
    out = tmp_path / "sw"
    assert main(["sweep", "--base-deck", str(deck), "--speeds", "21.75", "--angles", "0",
                 "--out", str(out), "--jobs", "1", "--quiet"]) == 0
    page = (out / "sweep.md").read_text()
    assert "steel40.dat" not in page and f"Base deck: `{deck}`" in page
    rows = list(csv.DictReader(io.StringIO((out / "sweep.csv").read_text())))
    assert [r["scene"] for r in rows] == ["car820_v21.75"]
    assert not any(r["scene"].startswith("steel") for r in rows)


def test_the_angle_bound_is_the_stability_studys_largest_angle(tmp_path):
    """sweep takes every angle the stability study runs (up to 90 degrees), and no more."""
    from deck_emulator.app import call
    from deck_emulator.errors import UsageError
    from deck_emulator.studies.stability import scenes

    base = read_deck(ROOT / "decks" / "steel40.dat").values
    for quick in (True, False):
        assert max(s["alpha_deg"] for s in scenes(base, quick) if "alpha_deg" in s) == 90
    with pytest.raises(UsageError, match="from 0 to 90 degrees"):
        call("sweep", speeds="40", angles="90.5", out=str(tmp_path / "x"))
    assert call("sweep", speeds="40", angles="90", erratum=("ed-direction",), jobs=1,
                quiet=True, out=str(tmp_path / "y")).exit_status == 0


def test_a_core_row_made_without_the_contact_force_is_the_whole_outcomes_row():
    """The sweep asks the core for the arrays its row reads (not the force on the car, which
    only pictures draw); the row is, value for value, the row of the outcome with every
    array."""
    import math

    from deck_emulator.decks import path as deck_path
    from deck_emulator.engine import CoreEngine

    assert "pulse" not in sweep.ROW_ARRAYS
    base = read_deck(deck_path("steel40"))
    cases = ((40.0, 0.0), (20.0, 15.0), (40.0, 30.0), (60.0, 45.0))
    decks = [sweep.scene_deck(base, s, a) for s, a in cases]
    whole = CoreEngine().run_batch(decks)
    lean = CoreEngine(arrays=sweep.ROW_ARRAYS).run_batch(decks)
    for (s, a), x, y in zip(cases, whole, lean):
        rx, ry = sweep.result_row(x, s, a), sweep.result_row(y, s, a)
        rx.pop("run_s"), ry.pop("run_s")
        assert rx.keys() == ry.keys()
        for k in rx:
            assert rx[k] == ry[k] or (isinstance(rx[k], float) and math.isnan(rx[k])
                                      and math.isnan(ry[k])), (s, a, k)
        assert x.pulse_t.size and not y.pulse_t.size


def test_a_core_batch_past_its_wall_bound_gives_stopped_rows_and_a_resume_runs_them(
        tmp_path, capsys, monkeypatch):
    """The compiled core's batch passes its wall bound (the defaults' row, here 0 s): the
    sweep writes its tables with the scenes' rows saying why they stopped, exits 3, and a
    resume runs those scenes again (the workers are this process's threads, so the bound set
    here holds in them)."""
    from distributed import LocalCluster

    from deck_emulator.cli import main
    from deck_emulator.studies.store import SceneStore
    from deck_emulator.vocabulary import defaults

    out = tmp_path / "s"
    bound = defaults.MAX_WALL_S
    monkeypatch.setattr(defaults, "MAX_WALL_S", 0.0)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                      dashboard_address=None) as cluster:
        argv = ["sweep", "--speeds", "40", "--angles", "0,15", "--engine", "core", "--quiet",
                "--out", str(out), "--scheduler", cluster.scheduler_address]
        assert main(argv) == 3
        assert "steel40, steel40_a15 stopped early" in capsys.readouterr().err
        with open(out / "sweep.csv", newline="") as f:
            errors = [r["error"] for r in csv.DictReader(f)]
        assert len(errors) == 2 and all("max_wall_s = 0 s" in e for e in errors)
        store = SceneStore(out / defaults.SCENE_STORE)
        assert [r["status"] for r in store.rows()] == ["stopped"] * 2 and not store.ids()
        monkeypatch.setattr(defaults, "MAX_WALL_S", bound)
        code = main([*argv, "--resume"])
        assert code == 0, capsys.readouterr().err
        with open(out / "sweep.csv", newline="") as f:
            assert [r["error"] for r in csv.DictReader(f)] == ["", ""]
    capsys.readouterr()


def test_a_defect_in_building_a_row_is_a_failed_scene_with_its_reason(monkeypatch):
    """A row that cannot be built (a defect of the program, here a stand-in raising) is not
    swallowed in the sweep: the batch raises, the runner runs each scene again alone, and the
    scene whose row fails is stored failed with the exception's line; the other is whole."""
    from deck_emulator.studies import distributed

    base = str(ROOT / "decks" / "steel40.dat")
    jobs = [dict(base=base, speed=float(s), angle=0.0, engine="emulator", options={},
                 post="steel", vvb_decimals=2) for s in (40, 20)]
    made = sweep.result_row

    def breaks_at_20(res, speed, angle, report=None):
        if speed == 20:
            raise TypeError("a defect in the row")
        return made(res, speed, angle, report)

    monkeypatch.setattr(sweep, "result_row", breaks_at_20)
    with pytest.raises(TypeError, match="a defect in the row"):
        sweep._stored_scene_jobs(jobs)
    rows = distributed._call_many(sweep._stored_scene_jobs, jobs, many=True)
    assert [r["status"] for r in rows] == ["ok", "failed"]
    assert rows[1]["error"] == "TypeError: a defect in the row"


def test_a_sweeps_rows_are_stored_as_columns_and_read_back_as_made(tmp_path):
    """The store holds each key of a row as a column of its own (no JSON text), and the sweep
    reads back the rows its worker made, value for value and type for type."""
    import pyarrow.parquet as pq

    from deck_emulator.studies.store import META_COLUMNS, SceneStore

    rows = sweep.sweep([20, 40], [0, 15], engine="emulator", options={"errata": ["ed-direction"]},
                       quiet=True, jobs=1, store_dir=tmp_path / "store")
    (first, *_) = SceneStore(tmp_path / "store").files()
    names = set(pq.read_schema(first).names)
    assert names == {*META_COLUMNS, *(sweep.ROW_PREFIX + k for k in sweep.ROW_KEYS)}
    jobs = [dict(base=str(sweep.POSTS["steel"]), speed=float(s), angle=float(a),
                 engine="emulator", options={"errata": ["ed-direction"]}, post="steel", vvb_decimals=2)
            for s in (20, 40) for a in (0, 15)]
    made = sweep._scene_rows(jobs)
    assert [r["scene"] for r in rows] == [r["scene"] for r in made]
    assert rows[3]["report_delta_v_crush_mph"] is not None  # steel40_a15: a report case
    for got, want in zip(rows, made):
        assert list(got) == list(want)
        for k in want:
            if k != "run_s":
                assert type(got[k]) is type(want[k]), k
                assert got[k] == want[k] or (want[k] != want[k] and got[k] != got[k]), k


def test_a_sweep_reads_its_base_deck_once(tmp_path, monkeypatch):
    """Given its base deck as the command read it (the deck and its file's SHA-256), a sweep
    reads that file no more: not for the store's study check, not for the report's cases
    (each other shipped deck it compares is read once), not in a worker."""
    from deck_emulator.studies import store

    base = sweep.POSTS["steel"]
    deck, sha = sweep.read_base(base)
    read = []
    real = sweep.read_deck
    monkeypatch.setattr(sweep, "read_deck", lambda path: read.append(str(path)) or real(path))
    monkeypatch.setattr(sweep, "read_bytes", lambda *a, **k: pytest.fail("read again"))
    monkeypatch.setattr(store, "_named_files", lambda tasks: pytest.fail("hashed again"))
    rows = sweep.sweep([20, 40], [0, 15], engine="emulator", base=base, base_deck=deck,
                       base_sha256=sha, quiet=True, jobs=1, store_dir=tmp_path / "store",
                       options={"errata": ["ed-direction"]})
    assert len(rows) == 4 and str(base) not in read and len(read) == len(set(read)) == 3
    study = (tmp_path / "store" / store.STUDY_NAME).read_text()
    assert sha == hashlib.sha256(Path(base).read_bytes()).hexdigest() and sha in study


def test_a_resume_on_rows_stored_as_json_by_an_earlier_sweep_is_refused(tmp_path):
    """A store whose ended scenes hold their row as one JSON text (an earlier sweep's) has no
    row columns to read back: --resume is refused, not answered with empty rows."""
    from deck_emulator.studies.store import SceneStore, StudyChanged

    store = tmp_path / "store"
    SceneStore(store).write_batch([{"scene_id": "0" * 24, "status": "ok",
                                    "row_json": '{"scene": "steel40"}'}])
    with pytest.raises(StudyChanged, match="earlier sweep"):
        sweep.sweep([40], [0], quiet=True, jobs=1, store_dir=store, resume=True)
