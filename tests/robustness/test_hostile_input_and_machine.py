"""Hostile input and a hostile machine -- a study resumed on a changed deck, a card image cut
short, a run past its wall bound, sources that are not files, scene files that are bombs,
schedulers that are not Dask's, closed streams, bare locales, process limits -- each held to
the tool's promise: a documented exit status (0 computed, 2 bad input and nothing written, 3 a
run that could not end), one line for a refusal, no traceback, no hang."""

from __future__ import annotations

import io
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from deck_emulator.cli import main

ROOT = Path(__file__).resolve().parents[2]
STEEL40 = ROOT / "decks" / "steel40.dat"


def _one_line(err: str) -> str:
    assert "Traceback" not in err, err
    lines = [x for x in err.splitlines() if x.startswith("deck-emulator: error:")]
    assert len(lines) == 1, err
    return lines[0]


# ------------------------------------------------------- a card image cut short (item 2)


@pytest.mark.parametrize("fmt", ["binary", "cbn", "bcd"])
@pytest.mark.parametrize("cut", [2, 8])
@pytest.mark.parametrize("command", [["parse"], ["summary", "--quiet"], ["run"]])
def test_a_punched_card_image_cut_short_is_refused(tmp_path, capsys, fmt, cut, command):
    whole = tmp_path / f"s.{fmt}"
    assert main(["punch", "steel40", "--to", fmt, "--out", str(whole)]) == 0
    data = whole.read_bytes()
    cut_file = tmp_path / f"t.{fmt}"
    cut_file.write_bytes(data[:-cut])
    capsys.readouterr()
    assert main([command[0], str(cut_file), *command[1:]]) == 2
    out, err = capsys.readouterr()
    line = _one_line(err)
    assert out == ""
    assert "card 9 of the file" in line  # steel40 is nine cards: the cut is in the last
    if fmt == "binary":
        assert f"card 9 has only {160 - cut}" in line
    else:
        size = {"cbn": 160, "bcd": 80}[fmt]
        last = len(data) - size  # the punch writes the last card whole
        assert f"(bytes {last}-{len(data) - cut - 1})" in line and "cut short" in line
    # the whole image reads as the deck (1200.0 lb, the report's FCONST)
    assert main(["parse", str(whole), "--json"]) == 0
    assert '"FCONST": 1200.0' in capsys.readouterr().out.replace("\n", "").replace("  ", " ")


# --------------------------------------------------- closed standard streams (item 7)


@pytest.mark.parametrize("argv", [
    ["run", "steel40"], ["parse", "steel40"], ["parse", "steel40", "--json"],
    ["summary", "steel40"], ["corrections", "--all"], ["scene", "steel40"],
])
def test_an_answer_for_a_closed_stdout_is_refused_before_work(monkeypatch, tmp_path, argv):
    err = io.StringIO()
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "stdout", None)  # as Python starts with descriptor 1 closed
    monkeypatch.setattr(sys, "stderr", err)
    assert main(argv) == 2
    assert sys.stdout is None  # put back as it was
    line = _one_line(err.getvalue())
    assert "standard output is closed" in line
    assert list(tmp_path.iterdir()) == []


def test_with_stdout_closed_an_answer_for_a_file_is_written(monkeypatch, tmp_path):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stdout", None)
    monkeypatch.setattr(sys, "stderr", err)
    assert main(["run", "steel40", "--out", str(tmp_path / "p.txt")]) == 0
    assert (tmp_path / "p.txt").read_text() == (ROOT / "golden" / "steel40.r8.txt").read_text()
    assert "Traceback" not in err.getvalue()


@pytest.mark.parametrize("argv, status", [
    (["parse", "no-such-deck"], 2), (["run", "steel40", "--max-ed-iterations", "1"], 3),
    (["run", "steel40", "--no-such-option"], 2)])
def test_with_stderr_closed_a_refusal_ends_with_its_status(monkeypatch, capsys, argv, status):
    monkeypatch.setattr(sys, "stderr", None)
    assert main(argv) == status
    assert "error" not in capsys.readouterr().out  # not said on stdout instead


@pytest.mark.slow
def test_a_process_started_with_stdout_or_stderr_closed(tmp_path):
    done = subprocess.run(
        [sys.executable, "-m", "deck_emulator.cli", "run", "steel40"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=120,
        preexec_fn=lambda: os.close(1))
    assert done.returncode == 2
    assert _one_line(done.stderr.decode()).endswith("standard output is closed, and the answer "
                                                    "goes there: give --out FILE, or open it")
    # stderr closed: the refusal's status, and nothing said on stdout
    done = subprocess.run(
        [sys.executable, "-m", "deck_emulator.cli", "parse", str(tmp_path / "missing.dat")],
        stdout=subprocess.PIPE, timeout=120, preexec_fn=lambda: os.close(2))
    assert (done.returncode, done.stdout) == (2, b"")


# --------------------------------------------------------------- a bare locale (item 8)


def _in_encoding(monkeypatch, encoding: str, argv: list[str]) -> tuple[int, bytes]:
    raw = io.BytesIO()
    stream = io.TextIOWrapper(raw, encoding=encoding, errors="strict", newline="\n")
    monkeypatch.setattr(sys, "stdout", stream)
    status = main(argv)
    stream.flush()
    return status, raw.getvalue()


@pytest.mark.parametrize("argv", [["parse", "steel40"], ["corrections", "--all"]])
@pytest.mark.parametrize("encoding", ["ascii", "latin-1"])
def test_output_in_an_encoding_without_the_units_characters_degrades(monkeypatch, encoding,
                                                                     argv):
    from deck_emulator.cli import ASCII_SPELLINGS

    status, utf8 = _in_encoding(monkeypatch, "utf-8", argv)
    text = utf8.decode("utf-8")
    assert status == 0 and not text.isascii()  # the case this is about
    status, narrow = _in_encoding(monkeypatch, encoding, argv)
    assert status == 0
    # each character the encoding has not got, and only those, spelled as the table says
    expected = "".join(ch if ch.encode(encoding, "ignore") else ASCII_SPELLINGS[ch]
                       for ch in text)
    assert narrow.decode(encoding) == expected


def test_standard_error_degrades_alike(monkeypatch):
    raw = io.BytesIO()
    stream = io.TextIOWrapper(raw, encoding="ascii", errors="strict", newline="\n")
    monkeypatch.setattr(sys, "stderr", stream)
    monkeypatch.setattr("deck_emulator.cli.PROG", "deck-emulator \u2014 \u03c8\u0307")
    assert main(["parse", "no-such-deck"]) == 2
    stream.flush()
    assert raw.getvalue().startswith(b"deck-emulator -- psi_dot: error: ")


def test_every_ascii_spelling_is_ascii():
    from deck_emulator.cli import ASCII_SPELLINGS

    for ch, spelled in ASCII_SPELLINGS.items():
        assert not ch.isascii() and spelled.isascii() and spelled, ch


@pytest.mark.slow
def test_a_bare_c_locale_process_writes_ascii_spellings():
    env = {"LC_ALL": "C", "PYTHONUTF8": "0", "PYTHONCOERCECLOCALE": "0"}
    env.pop("PYTHONIOENCODING", None)
    for argv, spelled in ((["parse", "steel40"], b"slug*ft^2"),
                          (["corrections", "--all"], b" -- ")):
        done = subprocess.run([sys.executable, "-m", "deck_emulator.cli", *argv],
                              capture_output=True, timeout=120,
                              env={k: v for k, v in {**os.environ, **env}.items()
                                   if k != "PYTHONIOENCODING"})
        assert done.returncode == 0, done.stderr
        assert b"Traceback" not in done.stderr and spelled in done.stdout
        assert done.stdout.isascii()


# ------------------------------------------------- a SOURCE that is not a regular file (item 4)


def _writer(path_or_fd, data: bytes, delay: float = 0.2) -> threading.Thread:
    """A thread that writes ``data`` to a FIFO (a path) or a pipe (a descriptor), then closes
    it, as a shell's writer would."""
    def write():
        time.sleep(delay)
        if isinstance(path_or_fd, int):
            with os.fdopen(path_or_fd, "wb") as fh:
                fh.write(data)
        else:
            with open(path_or_fd, "wb") as fh:
                fh.write(data)

    thread = threading.Thread(target=write, daemon=True)
    thread.start()
    return thread


def _body(out: str) -> str:
    """Output without its first line (parse names the file there)."""
    return out.split("\n", 1)[1]


def _golden_parse(capsys) -> str:
    assert main(["parse", str(STEEL40)]) == 0
    return _body(capsys.readouterr().out)


@pytest.mark.parametrize("command", ["parse", "run"])
def test_a_pipe_named_by_its_descriptor_is_read_once_as_its_deck(capsys, command):
    # what `deck-emulator parse <(cat D)` is given: /dev/fd/N, a pipe
    assert main([command, str(STEEL40)]) == 0
    expected = _body(capsys.readouterr().out)
    read, write = os.pipe()
    try:
        thread = _writer(write, STEEL40.read_bytes())
        assert main([command, f"/dev/fd/{read}"]) == 0
        thread.join(30)
    finally:
        os.close(read)
    assert _body(capsys.readouterr().out) == expected


def test_a_fifo_is_read_as_the_deck_its_writer_sends(tmp_path, capsys):
    expected = _golden_parse(capsys)
    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    thread = _writer(str(fifo), STEEL40.read_bytes(), delay=0.5)  # the reader waits for it
    assert main(["parse", str(fifo)]) == 0
    thread.join(30)
    assert _body(capsys.readouterr().out) == expected


def test_a_fifo_with_no_writer_is_refused_after_the_bound(tmp_path, capsys, monkeypatch):
    from deck_emulator.vocabulary import defaults

    monkeypatch.setattr(defaults, "SOURCE_WAIT_S", 0.5)
    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    started = time.monotonic()
    assert main(["run", str(fifo)]) == 2
    assert time.monotonic() - started < 30  # a hang guard, not a timing
    line = _one_line(capsys.readouterr().err)
    assert "nothing was written to it in 0.5 s" in line and str(fifo) in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f"]


def test_a_device_and_a_socket_are_refused_in_one_line(tmp_path, capsys):
    import socket

    assert main(["parse", "/dev/null"]) == 2
    assert "/dev/null: is a device, not a deck file" in _one_line(capsys.readouterr().err)
    sock = socket.socket(socket.AF_UNIX)
    try:
        sock.bind(str(tmp_path / "s"))
        assert main(["run", str(tmp_path / "s")]) == 2
        assert "is a socket, not a deck file" in _one_line(capsys.readouterr().err)
    finally:
        sock.close()


@pytest.mark.slow
@pytest.mark.parametrize("source", ["-", "/dev/stdin"])
@pytest.mark.parametrize("what", ["deck", "scene"])
def test_standard_input_as_a_pipe_is_the_source(tmp_path, source, what):
    if what == "deck":
        data, argv, says = STEEL40.read_bytes(), ["parse"], b"FCONST   1200.00000  lb"
    else:
        scene = tmp_path / "s.toml"
        assert main(["scene", "steel40", "--out", str(scene)]) == 0
        data, argv, says = scene.read_bytes(), ["scene"], scene.read_bytes()
    done = subprocess.run([sys.executable, "-m", "deck_emulator.cli", *argv, source],
                          input=data, capture_output=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert says in done.stdout


@pytest.mark.slow
def test_standard_input_from_a_terminal_or_device_is_refused():
    done = subprocess.run([sys.executable, "-m", "deck_emulator.cli", "run", "-"],
                          stdin=subprocess.DEVNULL, capture_output=True, timeout=120)
    assert done.returncode == 2
    assert _one_line(done.stderr.decode()).endswith("stdin: is a device, not a deck file "
                                                    "(give a file, a pipe or a FIFO)")


# ------------------------------------------------- scene and assembly files as bombs (item 5)

#: (name, text, what the refusal says): the campaign's bombs, and the bounds' own edges
BOMBS = [
    ("inline tables 1,000 deep", "a = " + "{b = " * 1000 + "1" + "}" * 1000 + "\n",
     "nested more than 16 deep"),
    ("arrays 100,000 deep", "a = " + "[" * 100_000 + "1" + "]" * 100_000 + "\n",
     "nested more than 16 deep"),
    ("a dotted key of 50,000 parts", "a" + ".a" * 50_000 + " = 1\n",
     "a dotted key of more than 16 parts"),
    ("a header of 50,000 parts", "[" + "a." * 50_000 + "a]\nx = 1\n",
     "a dotted key of more than 16 parts"),
    ("an integer of 100,000 digits", "[shaft]\nlength_ft = 1" + "0" * 100_000 + "\n",
     "shaft.length_ft: a number of more than 100 digits"),
    ("2 MB of comment", "#" * (2 << 20) + "\n", "larger than"),
]


@pytest.mark.parametrize("name, text, says", BOMBS, ids=[b[0] for b in BOMBS])
@pytest.mark.parametrize("command", [["core"], ["scene"], ["run"], ["assembly", "scene"]])
def test_a_bomb_of_a_scene_or_assembly_file_is_refused_in_one_line(tmp_path, capsys, name,
                                                                   text, says, command):
    bomb = tmp_path / "b.toml"
    bomb.write_text(text)
    assert main([command[0], str(bomb), *command[1:]]) == 2
    out, err = capsys.readouterr()
    assert says in _one_line(err) and out == ""
    assert [p.name for p in tmp_path.iterdir()] == ["b.toml"]


def test_the_bounds_hold_every_shipped_scene_and_description():
    from deck_emulator.vocabulary.toml_limits import check

    shipped = sorted((ROOT / "src" / "deck_emulator" / "assemblies").glob("*.toml"))
    assert shipped
    for path in shipped:
        check(path.read_text())


@pytest.mark.parametrize("depth, refused", [(16, False), (17, True)])
def test_the_nesting_bound_is_sixteen(depth, refused):
    from deck_emulator.vocabulary.toml_limits import TomlLimitError, loads

    text = "a = " + "[" * depth + "1" + "]" * depth + "\n"
    if refused:
        with pytest.raises(TomlLimitError, match="nested more than 16 deep"):
            loads(text)
    else:
        value = loads(text)["a"]
        for _ in range(depth):
            value = value[0]
        assert value == 1


def test_brackets_and_digits_inside_strings_and_comments_do_not_count():
    from deck_emulator.vocabulary.toml_limits import loads

    text = ('a = "' + "[" * 40 + "9" * 200 + '"\n' + "b = '''" + "{" * 40 + "'''\n"
            + "# " + "[" * 40 + "." * 40 + "\n" + '"x.y" = 1\n')
    assert loads(text)["b"] == "{" * 40


# ------------------------------------------------ a resume that trusts a changed deck (item 1)


def test_a_store_knows_the_files_and_scenes_it_was_made_from(tmp_path):
    from deck_emulator.studies.store import STUDY_NAME, StudyChanged, _check_study, scene_id

    deck = tmp_path / "b.dat"
    deck.write_bytes(STEEL40.read_bytes())

    def study(speeds, engine="emulator"):
        tasks = [{"base": str(deck), "speed": s, "angle": 0.0, "engine": engine}
                 for s in speeds]
        return {scene_id(t): t for t in tasks}

    unique = study([20.0, 40.0])
    store = tmp_path / "store"
    store.mkdir()
    _check_study(store, unique, set())  # a new store keeps it
    assert (store / STUDY_NAME).is_file()
    stored = set(unique)
    _check_study(store, unique, stored)  # the same study: resumed
    # W changed from 15.1 to 15.2 slugs: another deck under the same name
    deck.write_bytes(STEEL40.read_bytes().replace(b"15.1      ", b"15.2      ", 1))
    with pytest.raises(StudyChanged, match=r"b\.dat changed since .*store was made from it"):
        _check_study(store, unique, stored)
    deck.write_bytes(STEEL40.read_bytes())
    _check_study(store, unique, stored)  # back as it was: resumed
    wider = study([20.0, 40.0, 60.0])  # a grid made larger keeps the scenes both share
    _check_study(store, wider, stored)
    core = study([20.0, 40.0], engine="core")  # another engine: no stored scene is asked for
    with pytest.raises(StudyChanged, match=r"none of the 2 scenes stored in .* is among the 2"):
        _check_study(store, core, stored)
    (store / STUDY_NAME).write_text("{")
    with pytest.raises(StudyChanged, match="unreadable"):
        _check_study(store, unique, stored)


@pytest.mark.slow
def test_a_sweep_resumed_on_a_changed_deck_is_refused(tmp_path, capsys):
    deck = tmp_path / "b.dat"
    deck.write_bytes(STEEL40.read_bytes())
    out = tmp_path / "D"
    argv = ["sweep", "--base-deck", str(deck), "--speeds", "20", "--angles", "0",
            "--erratum", "ed-direction", "--quiet", "--jobs", "1", "--out", str(out)]
    assert main(argv) == 0
    table = (out / "sweep.csv").read_bytes()
    assert main([*argv, "--resume"]) == 0  # the same study: resumed, the same table
    assert (out / "sweep.csv").read_bytes() == table
    capsys.readouterr()
    deck.write_bytes(STEEL40.read_bytes().replace(b"15.1      ", b"15.2      ", 1))
    assert main([*argv, "--resume"]) == 2
    line = _one_line(capsys.readouterr().err)
    assert f"{deck} changed since" in line and "--resume" in line
    assert (out / "sweep.csv").read_bytes() == table  # nothing written


# ------------------------------------------ a core run past its wall bound is stopped (item 3)


def test_a_core_run_past_its_wall_bound_is_a_stopped_scene(monkeypatch):
    from deck_emulator.studies import common
    from deck_emulator.studies.store import Stopped
    from deck_emulator.vocabulary import defaults
    from deck_emulator.vocabulary.scene import LEGACY, Scene

    from deck_emulator.legacy.deck import read_deck

    scene = Scene.from_deck(read_deck(STEEL40))
    monkeypatch.setattr(defaults, "MAX_WALL_S", 0.0)  # any run passes it at its first step
    with pytest.raises(Stopped, match=r"max_wall_s = 0 s .*starved or suspended machine"):
        common.run_core(scene, LEGACY)


def test_a_study_whose_core_run_passes_its_wall_bound_stops_and_its_resume_runs_it(
        tmp_path, capsys, monkeypatch):
    """The study ended in KeyError: 'guard', and every resume again: the stopped run was
    stored as done.  Now exit 3 naming the run, nothing but the store written, and a resume
    runs each stopped scene again (the workers are this process's threads, so the bound set
    here holds in them)."""
    from collections import Counter

    from distributed import LocalCluster

    from deck_emulator.studies.store import SceneStore
    from deck_emulator.vocabulary import defaults

    monkeypatch.setattr(defaults, "MAX_WALL_S", 0.0)
    out = tmp_path / "e"
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                      dashboard_address=None) as cluster:
        argv = ["study", "error", "steel40", "--quick", "--quiet", "--out", str(out),
                "--scheduler", cluster.scheduler_address]
        assert main(argv) == 3
        line = _one_line(capsys.readouterr().err)
        assert "stopped: CoreError" in line and "max_wall_s = 0 s" in line
        assert "--resume runs it again" in line
        store = SceneStore(out / defaults.SCENE_STORE)
        first = Counter(r["scene_id"] for r in store.rows() if r["status"] == "stopped")
        assert first and not store.ids()  # stored, and none counted as done
        assert sorted(p.name for p in out.iterdir()) == [defaults.SCENE_STORE]
        assert main([*argv, "--resume"]) == 3  # still past the bound: run again, stopped again
        again = Counter(r["scene_id"] for r in store.rows() if r["status"] == "stopped")
        assert again == Counter({sid: 2 for sid in first})
    capsys.readouterr()


# ------------------------------------------------------- schedulers that are not Dask's (item 6)


SCHEDULER_COMMANDS = {
    "sweep": ["sweep", "--speeds", "20", "--angles", "0"],
    "study error": ["study", "error", "steel40", "--quick"],
    "sensitivity": ["sensitivity", "--quick"],
}


@pytest.mark.parametrize("command", sorted(SCHEDULER_COMMANDS))
@pytest.mark.parametrize("mode, says", [
    ("silent", "something took the connection and said nothing a Dask scheduler says in 2 s"),
    ("drip", "something took the connection and said nothing a Dask scheduler says in 2 s"),
    ("http", "something answered there, not in Dask's protocol (not a Dask scheduler)"),
    ("refused", "nothing listens there ("),
    ("tls", "tls:// needs Dask's TLS settings"),
    ("ucx", "this install cannot connect so"),
])
def test_a_scheduler_that_is_not_dasks_is_refused_within_the_bound(tmp_path, capsys,
                                                                   monkeypatch, command,
                                                                   mode, says):
    from deck_emulator.vocabulary import defaults

    from campaign import Hostile

    monkeypatch.setattr(defaults, "SCHEDULER_CONNECT_S", 1.0)
    server = (Hostile("answer", b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")
              if mode == "http" else Hostile(mode, b"x") if mode in ("silent", "drip", "refused")
              else None)
    address = server.address if server else f"{mode}://127.0.0.1:8786"
    try:
        started = time.monotonic()
        status = main([*SCHEDULER_COMMANDS[command], "--quiet", "--out", str(tmp_path / "o"),
                       "--scheduler", address])
        assert time.monotonic() - started < 30  # a hang guard, not a timing
    finally:
        if server:
            server.close()
    assert status == 2
    line = _one_line(capsys.readouterr().err)
    assert f"--scheduler {address}: {says}" in line
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_a_dask_worker_given_as_the_scheduler_is_refused(tmp_path, capsys):
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, processes=False, protocol="tcp://",
                      dashboard_address=None) as cluster:
        worker = next(iter(cluster.scheduler.workers))
        assert main(["sweep", "--speeds", "20", "--angles", "0", "--quiet", "--out",
                     str(tmp_path / "o"), "--scheduler", worker]) == 2
        assert "a Dask Worker answered there, not a Dask scheduler" in _one_line(
            capsys.readouterr().err)
        # the scheduler itself is taken
        assert main(["sweep", "--speeds", "20", "--angles", "0", "--quiet", "--out",
                     str(tmp_path / "o"), "--scheduler", cluster.scheduler_address]) == 0


# ------------------------------------------------------------------------- limits (item 9)


def _limited(argv: list[str], cwd=None, **limits) -> subprocess.CompletedProcess:
    """A command in a process of its own under ``limits`` (resource name -> soft and hard)."""
    import resource

    def limit():
        for name, value in limits.items():
            resource.setrlimit(getattr(resource, name), (value, value))

    return subprocess.run([sys.executable, "-m", "deck_emulator.cli", *argv], cwd=cwd,
                          preexec_fn=limit, capture_output=True, timeout=300)


@pytest.mark.slow
@pytest.mark.parametrize("files, says", [
    (15, "the open-file limit (15, ulimit -n) is too low for 2 worker process(es)"),
    (16, "give --jobs 1, or raise it (ulimit -n 1024)")])
def test_an_open_file_limit_too_low_for_the_workers_is_said_before_they_start(tmp_path, files,
                                                                              says):
    done = _limited(["sweep", "--speeds", "20,30", "--angles", "0", "--jobs", "2", "--quiet",
                     "--out", str(tmp_path / "o")], RLIMIT_NOFILE=files)
    assert done.returncode == 2
    assert says in _one_line(done.stderr.decode())
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
@pytest.mark.parametrize("argv", [["sweep", "--speeds", "20,30", "--angles", "0", "--jobs", "2"],
                                  ["core", "steel40"]])
@pytest.mark.parametrize("megabytes", [200, 400, 800])
def test_under_an_address_space_limit_a_command_ends_or_says_which_limit(tmp_path, argv,
                                                                         megabytes):
    out = ["--quiet", "--out", str(tmp_path / "o")] if argv[0] == "sweep" else []
    done = _limited([*argv, *out], RLIMIT_AS=megabytes << 20)
    err = done.stderr.decode()
    assert done.returncode in (0, 2), err  # computed, or refused in one line
    if done.returncode == 2:
        assert "(ulimit -v): raise them" in _one_line(err)
        assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_a_sweep_from_a_deleted_folder_runs(tmp_path):
    gone = tmp_path / "gone"
    gone.mkdir()
    done = subprocess.Popen(
        [sys.executable, "-c", "import os, sys; os.rmdir(os.getcwd()); "
         "from deck_emulator.cli import main; sys.exit(main(sys.argv[1:]))",
         "sweep", "--speeds", "20", "--angles", "0", "--jobs", "1", "--quiet",
         "--out", str(tmp_path / "o")], cwd=gone, stderr=subprocess.PIPE)
    _, err = done.communicate(timeout=300)
    assert done.returncode == 0, err
    assert (tmp_path / "o" / "sweep.csv").is_file()


# ------------------------------------------------------------------ smaller promises (item 10)


@pytest.mark.parametrize("epoch", ["abc", "1e9", "253402300800", "-1", " 1"])
def test_a_source_date_epoch_that_is_not_whole_seconds_is_refused(tmp_path, capsys,
                                                                  monkeypatch, epoch):
    monkeypatch.setenv("SOURCE_DATE_EPOCH", epoch)
    assert main(["run", "steel40", "--pages", str(tmp_path / "p.pdf")]) == 2
    assert "SOURCE_DATE_EPOCH=" in _one_line(capsys.readouterr().err)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("length", [240, 250, 255])
def test_a_legal_output_name_of_up_to_255_bytes_is_written(tmp_path, length):
    from deck_emulator.files import write_file

    name = tmp_path / ("t" * (length - 4) + ".csv")
    write_file(name, "x\n")
    assert name.read_text() == "x\n" and [p.name for p in tmp_path.iterdir()] == [name.name]


def test_a_folder_with_undecodable_bytes_holds_the_store_and_the_tables(tmp_path, monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # (a process's stderr escapes them)
    out = Path(os.fsdecode(bytes(tmp_path) + b"/x\xff"))
    assert main(["sweep", "--speeds", "20", "--angles", "0", "--jobs", "1", "--quiet",
                 "--out", str(out)]) == 0
    assert {p.name for p in out.iterdir()} == {"sweep.csv", "sweep.md", ".scenes"}
    assert bytes(out) in (out / "sweep.md").read_bytes()  # the bytes as given


def test_a_temporary_store_is_in_the_commands_own_temporary_folder():
    """So a killed run's store goes with that folder, which the next command removes
    (files.own_temp_folder; test_fault_items.py shows it for multiprocessing's pymp-*)."""
    from deck_emulator.files import own_temp_folder
    from deck_emulator.studies.distributed import temporary_store

    with temporary_store("sweep-") as tmp:
        assert Path(tmp).parent == Path(own_temp_folder()) and Path(tmp).is_dir()
    assert not Path(tmp).exists()
