"""Sobol indices: the analysis recovers the Ishigami function's closed-form indices through the
same path the engines take (sample -> run_scenes on Dask -> store -> SALib); the inputs and the
one engine adapter."""

from __future__ import annotations

import math

import pytest

from deck_emulator.studies import sensitivity as sa

# Independent source: the closed form (Ishigami and Homma 1990), a = 7, b = 0.1, as tabulated
# in the literature (e.g. Saltelli et al., Global Sensitivity Analysis: The Primer, 2008).
ISHIGAMI = {
    "S1": {"x1": 0.3139, "x2": 0.4424, "x3": 0.0},
    "ST": {"x1": 0.5576, "x2": 0.4424, "x3": 0.2437},
}


def test_closed_form_matches_the_published_values():
    got = sa.ishigami_indices(7.0, 0.1)
    for kind in ("S1", "ST"):
        for k, v in ISHIGAMI[kind].items():
            assert got[kind][k] == pytest.approx(v, abs=6e-5)


def test_ishigami_indices_are_recovered_within_their_confidence_intervals(tmp_path):
    problem = {"num_vars": 3, "names": ["x1", "x2", "x3"], "bounds": [[-math.pi, math.pi]] * 3}
    study = sa.run_study(
        problem, 1024, sa.ishigami_task, base_task={"a": 7.0, "b": 0.1}, outputs=["y"],
        store_dir=tmp_path / "s", jobs=2, digits=False, progress=False, chunk=256,
    )
    assert len(study.store.rows()) == 1024 * 5
    rows = [r for r in study.indices if r["N"] == 1024]
    assert len(rows) == 3
    for r in rows:
        for kind in ("S1", "ST"):
            truth = ISHIGAMI[kind][r["input"]]
            conf = r[f"{kind}_conf"]
            assert 0 < conf < 0.1, (r["input"], kind, conf)
            assert abs(r[kind] - truth) <= conf, (r["input"], kind, r[kind], conf, truth)
    # the half sample is reported too, with wider intervals on the whole
    half = [r for r in study.indices if r["N"] == 512]
    assert sum(r["ST_conf"] for r in half) > sum(r["ST_conf"] for r in rows)


def test_friction_inputs_exist_only_on_the_core():
    inputs, notes = sa.choose_inputs("core", [])
    assert [i.name for i in inputs] == [i.name for i in sa.DEFAULT_INPUTS]
    assert notes == []
    inputs, notes = sa.choose_inputs("emulator", [])
    assert "friction_lb" not in [i.name for i in inputs] and "CK" in [i.name for i in inputs]
    assert notes and "no field" in notes[0]
    with pytest.raises(ValueError, match="no base-friction field"):
        sa.choose_inputs("emulator", [sa.parse_input("friction_lb=500:900")])


def test_input_ranges_are_parsed_and_checked():
    r = sa.parse_input("HTV=-16:-14.5")
    assert (r.name, r.low, r.high) == ("HTV", -16.0, -14.5)
    for bad in ("HTV=1", "HTV=2:1", "NOPE=1:2", "CK"):
        with pytest.raises(ValueError):
            sa.parse_input(bad)
    inputs, _ = sa.choose_inputs("core", [sa.parse_input("CK=1000:2000")], defaults=False)
    assert [(i.name, i.low, i.high) for i in inputs] == [("CK", 1000.0, 2000.0)]


def test_the_nominal_friction_through_the_adapter_is_the_listing_run():
    def run(inputs):
        (row,) = sa.scene_tasks([{"deck": "steel40", "engine": "core", "preset": "legacy",
                                  "inputs": inputs}])
        return row

    plain = run({})
    nominal = run({"friction_lb": sa.LISTING_FRICTION_LB, "friction_travel_ft": 0.079333})
    changed = run({"friction_lb": 465.0})
    for k in sa.OUTCOMES:
        assert nominal[k] == pytest.approx(plain[k], rel=1e-9, abs=1e-12), k
    assert changed["delta_v_contact_mph"] != pytest.approx(plain["delta_v_contact_mph"], rel=1e-6)


def test_a_batch_of_scenes_gives_each_its_own_outcomes():
    """The worker's batch function (the core's scenes through CoreEngine.run_batch, grouped by
    engine: the friction inputs make another engine) gives every task what it gives the task
    alone; an unknown input fails its task only."""
    base = {"deck": "steel40", "engine": "core", "preset": "legacy"}
    tasks = [{**base, "inputs": {"WV": 80.0}},
             {**base, "inputs": {"friction_lb": 700.0, "CK": 30000.0}},
             {**base, "inputs": {"NOPE": 1.0}},
             {**base, "inputs": {"WV": 120.0, "FCONST": 9000.0}},
             {**base, "engine": "emulator", "inputs": {"WV": 90.0}}]
    together = sa.scene_tasks(tasks)
    assert isinstance(together[2], ValueError) and "NOPE" in str(together[2])
    for i, task in enumerate(tasks):
        if i == 2:
            continue
        a, b = dict(together[i]), dict(sa.scene_tasks([task])[0])
        assert a.pop("engine_run_s") > 0 and b.pop("engine_run_s") > 0
        assert a == b and a["engine_error"] == "" and a["hit_surface"] != "NONE", i
    assert together[0]["delta_v_crush_mph"] != together[3]["delta_v_crush_mph"]


def test_subcommand_registers():
    from deck_emulator.cli import build_parser

    args = build_parser().parse_args(
        ["sensitivity", "--quick", "--engine", "core", "--input", "HTV=-16:-14", "--deck",
         "steel20", "--deck", "steel40", "--scheduler", "tcp://h:8786", "--resume", "--out", "d"]
    )
    assert args.quick and args.resume and args.deck == ["steel20", "steel40"]
    assert args.scheduler == "tcp://h:8786" and args.command == "sensitivity"


def test_the_confidence_intervals_are_the_same_at_every_run():
    """The bootstrap of the intervals is seeded from the study's seed, the default 0 included
    (SALib takes a seed of 0 as none)."""
    import numpy as np

    from deck_emulator.studies.sensitivity import DEFAULT_INPUTS, analyse, problem_for, sample

    problem = problem_for(DEFAULT_INPUTS[:3])
    X = sample(problem, 16, seed=0)
    Y = {"y": X[:, 0] + 2 * X[:, 1] ** 2 / X[:, 1].max()}
    first, second = (analyse(problem, Y, [16], seed=0) for _ in range(2))
    assert [r["S1_conf"] for r in first] == [r["S1_conf"] for r in second]
    assert all(np.isfinite(r["S1_conf"]) for r in first)


# ---- options checked before any work; the same seed, the same bytes ---------


@pytest.mark.parametrize("n,seed,needle", [
    (0, 0, "power of two"), (3, 0, "power of two"), (1, 0, "power of two"),
    (-4, 0, "power of two"), (1 << 20, 0, "at most"), (16, -1, "seed"),
])
def test_n_and_seed_are_checked(n, seed, needle):
    with pytest.raises(ValueError, match=needle) as info:
        sa.check_options(n, seed)
    assert "\n" not in str(info.value)


def test_good_n_and_seed_pass():
    for n in (None, 2, 16, 256, 1024, sa.MAX_N):  # 1024: the 8,192-scene study
        sa.check_options(n, 0)
    sa.check_options(16, 12345)


@pytest.mark.parametrize("text", ["W=-inf:inf", "W=nan:1", "W=0:inf"])
def test_input_bounds_must_be_finite(text):
    with pytest.raises(ValueError, match="finite"):
        sa.parse_input(text)


@pytest.mark.parametrize("extra", [["-N", "0"], ["-N", "3"], ["--seed", "-1"],
                                   ["--input", "W=-inf:inf"]])
def test_bad_options_exit_2_and_write_nothing(tmp_path, capsys, extra):
    from deck_emulator.cli import main

    out = tmp_path / "study"
    assert main(["sensitivity", *extra, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists()


def test_a_missing_parent_folder_is_refused(tmp_path, capsys):
    from deck_emulator.cli import main

    assert main(["sensitivity", "--out", str(tmp_path / "a" / "missing" / "d")]) == 2
    assert not (tmp_path / "a").exists()
    assert "does not exist" in capsys.readouterr().err


@pytest.mark.parametrize("seed", [0, 7])
def test_the_same_seed_gives_byte_identical_tables(tmp_path, seed):
    problem = {"num_vars": 3, "names": ["x1", "x2", "x3"], "bounds": [[-math.pi, math.pi]] * 3}
    tables = []
    for k, jobs in enumerate((1, 2)):  # other workers, other order of finishing
        st = sa.run_study(problem, 32, sa.ishigami_task, base_task={"a": 7.0, "b": 0.1},
                          outputs=["y"], store_dir=tmp_path / f"s{k}", seed=seed, jobs=jobs,
                          digits=False, progress=False)
        tables.append(sa.indices_csv([{**r, "deck": "-", "engine": "-"} for r in st.indices]))
    assert tables[0] == tables[1]
    assert "nan" not in tables[0].lower()


def test_a_study_whose_every_scene_fails_exits_3_without_tables(tmp_path, capsys):
    from deck_emulator.cli import main

    out = tmp_path / "study"
    # a post of negative mass: the core refuses every scene of the range
    code = main(["sensitivity", "-N", "2", "--only", "--input", "W=-1:-0.5", "--jobs", "1",
                 "--out", str(out)])
    assert code == 3
    err = capsys.readouterr().err
    assert "every scene failed" in err and "mass must be positive" in err
    assert not (out / "sensitivity.csv").exists() and not (out / "sensitivity.md").exists()


def test_a_studys_rows_are_the_whole_outcomes_numbers_bit_for_bit():
    """The study's rows (its engine asked only for the arrays its quantities read, its row
    made from those quantities) hold, number for number, what the sweep's row says of the
    same scenes' whole outcomes (every array made): the same definitions, the same numbers.
    The sample's own scenes (friction inputs included), one that stops at its cap on the
    spring force and one on the emulator."""
    import dataclasses

    from deck_emulator.engine import CoreEngine
    from deck_emulator.studies.sweep import result_row
    from deck_emulator.vocabulary.defaults import OUTCOME_ARRAYS

    base = {"deck": "steel40", "engine": "core", "preset": "legacy"}
    problem = sa.problem_for(sa.DEFAULT_INPUTS)
    tasks = sa.tasks_for(problem, sa.sample(problem, 4), base)
    tasks += [{**base, "inputs": {"WV": 120.0, "FCONST": 9000.0}},
              {**base, "engine": "emulator", "inputs": {"WV": 90.0}}]
    rows = sa.scene_tasks(tasks)
    assert len(rows) == len(tasks) == 4 * 8 + 2
    for task, row in zip(tasks, rows):
        engine, deck, name, scene = sa._prepare(task["inputs"], task["engine"],
                                                task["preset"], task["deck"])
        if isinstance(engine, CoreEngine):
            assert engine.arrays == ("car", "points")  # oiv's pulse, the roof clearance
            engine = dataclasses.replace(engine, arrays=OUTCOME_ARRAYS)
            (whole,) = engine.run_batch([scene if scene is not None else deck], names=[name])
            assert whole.pulse_t.size  # every array made
        else:
            whole = engine.run(deck, name=name)
        ref = result_row(whole, whole.speed_mph, whole.angle_deg)
        surface = ref["hit_surface"].upper()
        expected = {
            "hit_surface": surface or "NONE",
            "hits_car": float(surface != "GROUND") if surface else None,
            "hits_roof": float(surface in ("WINDSHIELD", "TOP")) if surface else None,
            "hit_time_ms": None if ref["hit_time_s"] is None else 1000 * ref["hit_time_s"],
            **{k: ref[k] for k in ("delta_v_crush_mph", "delta_v_contact_mph", "max_decel_g",
                                   "oiv_m_s", "roof_clearance_ft")},
            "engine_error": ref["error"],
        }
        got = dict(row)
        assert got.pop("engine_run_s") > 0
        assert got == expected, task
    assert sum(r["roof_clearance_ft"] is not None for r in rows) > 0
    assert len({r["delta_v_contact_mph"] for r in rows}) > 20


def test_a_batch_past_its_wall_bound_stops_its_scenes_and_a_resume_runs_them(
        tmp_path, capsys, monkeypatch):
    """A starved or suspended machine: the compiled core's batch passes its wall bound (the
    defaults' row, here 0 s), its scenes are stored as stopped, the command exits 3 without
    tables, and a resume runs them again -- to the end once the machine keeps up (the workers
    are this process's threads, so the bound set here holds in them)."""
    from collections import Counter

    from distributed import LocalCluster

    from deck_emulator.cli import main
    from deck_emulator.studies.store import SceneStore
    from deck_emulator.vocabulary import defaults

    out = tmp_path / "s"
    bound = defaults.MAX_WALL_S
    monkeypatch.setattr(defaults, "MAX_WALL_S", 0.0)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                      dashboard_address=None) as cluster:
        argv = ["sensitivity", "-N", "2", "--quiet", "--out", str(out),
                "--scheduler", cluster.scheduler_address]
        assert main(argv) == 3
        err = capsys.readouterr().err
        assert "16 of 16 scenes stopped" in err and "max_wall_s = 0 s" in err
        assert "--resume runs the rest" in err
        store = SceneStore(out / defaults.SCENE_STORE / "steel40")
        first = Counter(r["scene_id"] for r in store.rows() if r["status"] == "stopped")
        assert len(first) == 16 and not store.ids()  # stored, none counted as done
        assert not (out / "sensitivity.csv").exists()
        monkeypatch.setattr(defaults, "MAX_WALL_S", bound)
        assert main([*argv, "--resume"]) == 0
        assert "steel40: 16 scenes, 16 run now" in capsys.readouterr().err
        assert store.ids() == set(first) and (out / "sensitivity.csv").exists()


# ------------------------------------------------- what the model cannot see, and what is noise

import numpy as np  # noqa: E402 - the tests above import it where they use it


def _problem(names=("a", "b", "c")):
    return {"num_vars": len(names), "names": list(names), "bounds": [[0.0, 1.0]] * len(names)}


def test_an_outcome_nearly_constant_gets_no_indices_and_says_in_how_many_scenes():
    """An indicator that is 1 in 3 of 512 scenes (N = 64, D = 6: the issue's steel20 run) is
    constant in 509 of them: at or past the defaults' fraction (0.99), so no indices; with
    more scenes differing (fewer than 99 % alike) it gets them."""
    from deck_emulator.studies.sensitivity import analyse
    from deck_emulator.vocabulary import defaults

    problem = _problem(tuple("abcdef"))
    y = np.zeros(512)
    y[[5, 100, 300]] = 1.0
    rows = analyse(problem, {"hits_car": y}, [64])
    assert {r["note"] for r in rows} == {"constant (0) in 509 of 512 scenes: no indices"}
    assert all(r["S1"] is None and r["ST"] is None for r in rows)
    assert 509 / 512 >= defaults.SENSITIVITY_CONSTANT_FRACTION > 498 / 512
    y[:: 512 // 14][:14] = 1.0  # 14 + 3 scenes differ (or fewer where they meet): < 99 % alike
    assert (y == 0).sum() < defaults.SENSITIVITY_CONSTANT_FRACTION * 512
    assert all(r["note"] == "" and r["ST"] is not None
               for r in analyse(problem, {"hits_car": y}, [64]))


@pytest.mark.parametrize("index, half, expected", [
    (0.5, 0.25, False),  # [0.25, 0.75]: exactly half of [0, 1] -- not more: resolved
    (0.5, 0.25 + 2 ** -20, True),  # a hair more than half
    (1.0, 0.9, True),  # the ST 1.0 +- 0.9: [0.1, 1] after clipping
    (0.0, 0.5, False),  # [0, 0.5] after clipping: half
    (0.9, 0.05, False),
    (float("nan"), 0.1, True), (0.3, float("nan"), True), (None, None, True),
])
def test_an_index_is_unresolved_when_its_interval_covers_most_of_zero_to_one(index, half,
                                                                             expected):
    from deck_emulator.studies.sensitivity import unresolved
    from deck_emulator.vocabulary import defaults

    assert defaults.SENSITIVITY_UNRESOLVED_SPAN == 0.5  # the cases above are built on it
    assert unresolved(index, half) is expected


def test_unresolved_indices_are_printed_as_such_not_as_numbers():
    from deck_emulator.studies.sensitivity import NOT_RESOLVED, indices_markdown

    base = {"deck": "d", "engine": "core", "output": "oiv_m_s", "N": 8, "scenes": 64,
            "missing": 0, "mean": 1.0, "sd": 0.1, "note": ""}
    rows = [{**base, "input": "a", "S1": 1.0, "S1_conf": 0.9, "ST": 1.0, "ST_conf": 0.9,
             "unresolved": "S1 ST"},
            {**base, "input": "b", "S1": 0.9, "S1_conf": 0.9, "ST": 0.42, "ST_conf": 0.05,
             "unresolved": "S1"}]
    page = indices_markdown(rows)
    line = next(x for x in page.splitlines() if x.startswith("| occupant impact velocity"))
    cells = [c.strip() for c in line.strip("|").split("|")][1:]
    assert cells == [NOT_RESOLVED, f"S1 {NOT_RESOLVED} / **0.42**±0.05"]
    assert "±0.90" not in line and "0.90±" not in line  # the unresolved numbers are not shown


def test_a_model_that_tests_only_points_is_blind_to_the_hits_and_says_so():
    from deck_emulator.studies import sensitivity as sa

    for engine, kw in (("emulator", {}), ("core", {"preset": "legacy"}),
                       ("core", {"preset": "legacy", "shaft_contact": False}),
                       ("core", {"preset": "physical", "shaft_contact": False})):
        assert set(sa.blind_outcomes(engine, kw)) == set(sa.CAR_TEST_OUTCOMES), (engine, kw)
    for kw in ({"preset": "legacy", "shaft_contact": True}, {"preset": "physical"}):
        assert sa.blind_outcomes("core", kw) == {}
    blind = sa.blind_outcomes("emulator", {})
    y = np.arange(64, dtype=float)  # a varying outcome: only blindness withholds it
    rows = sa.analyse(_problem(), {"hits_car": y, "oiv_m_s": y}, [8], blind=blind)
    hits = [r for r in rows if r["output"] == "hits_car"]
    assert all(r["S1"] is None and r["mean"] is None and r["note"].startswith("blind")
               for r in hits)
    assert all(r["S1"] is not None for r in rows if r["output"] == "oiv_m_s")
    first = sa.blind_line(blind)
    assert first.startswith("BLIND to P(first hit on the car)")


def test_the_study_tests_the_shaft_by_default(monkeypatch, tmp_path):
    """The command hands the study the core with shaft contact on unless told otherwise."""
    from deck_emulator.app import sensitivity as app
    from deck_emulator.studies import sensitivity as sa

    seen = {}
    monkeypatch.setattr(sa, "run_command", lambda **kw: seen.update(kw) or [])
    monkeypatch.setattr(app.common, "compile_core", lambda quiet: None)
    for argv, expected in (([], True), (["--no-shaft-contact"], False),
                           (["--shaft-contact"], True)):
        from deck_emulator.cli import main

        seen.clear()
        main(["sensitivity", "--out", str(tmp_path / "s"), "--quiet", *argv])
        assert seen["engine_keywords"]["shaft_contact"] is expected, argv
