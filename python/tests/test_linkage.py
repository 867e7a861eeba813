"""The Python package against the `linkage` binary: the same reports, the same time
histories, the same errors (file:line:column), and the spring-mass frequency law.

The binary is $LINKAGE_BIN, else target/release/linkage (built by `cargo build --release`);
without it these tests fail under CI and are skipped elsewhere.
"""

import csv
import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import linkage

ROOT = Path(__file__).resolve().parents[2]
SPRING_MASS = ROOT / "examples" / "spring_mass.adm"
FOURBAR = ROOT / "mechanisms" / "fourbar.adm"
DOOR = ROOT / "mechanisms" / "door_tilted_hinge.adm"


@pytest.fixture(scope="module")
def cli():
    binary = Path(os.environ.get("LINKAGE_BIN", ROOT / "target" / "release" / "linkage"))
    if not binary.is_file():
        if os.environ.get("CI"):
            pytest.fail(f"{binary} is missing under CI (cargo build --release -p linkage-cli)")
        pytest.skip(f"{binary} is missing: build it with cargo build --release -p linkage-cli")

    def run(*args):
        done = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True)
        return done.returncode, done.stdout, done.stderr

    return run


def plain(value):
    """A package value with numpy arrays turned back into (nested) lists."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, list):
        return [plain(v) for v in value]
    return value


def cli_json(cli, *args):
    code, out, err = cli(*args, "--format", "json")
    assert code == 0, err
    return json.loads(out)


@pytest.mark.parametrize("model", [SPRING_MASS, FOURBAR])
def test_verify_ic_and_linear_equal_the_cli_json(cli, model):
    m = linkage.load(str(model))
    assert plain(m.verify()) == cli_json(cli, "verify", model)
    assert plain(m.ic()) == cli_json(cli, "ic", model)
    assert plain(m.linear()) == cli_json(cli, "linear", model)


def test_static_equals_the_cli_json(cli):
    m = linkage.load(str(SPRING_MASS))
    assert plain(m.static()) == cli_json(cli, "static", SPRING_MASS)


def test_vectors_and_matrices_are_numpy_arrays():
    m = linkage.load(str(SPRING_MASS))
    ic = m.ic()
    part = ic["parts"][0]
    assert isinstance(part["position"], np.ndarray) and part["position"].shape == (3,)
    assert part["position"].dtype == np.float64
    # Nested lists of equal length are 2-D arrays.
    modes = m.linear()["modes"]
    assert isinstance(modes, list) and modes[0]["number"] == 1


def test_simulate_equals_the_cli_csv_and_summary(cli, tmp_path):
    out = tmp_path / "run.csv"
    code, stdout, err = cli("simulate", SPRING_MASS, "--end", "0.5", "--steps", "50", "--out", out,
                            "--format", "json")
    assert code == 0, err
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    m = linkage.load(str(SPRING_MASS))
    columns = m.simulate(end=0.5, steps=50)
    # Plain names as keys ("time", "block.z"); the CSV header's unit suffixes in m.units.
    names = [h.rsplit(" [", 1)[0] for h in header]
    assert list(columns) == names
    assert names[:2] == ["time", "block.x"]
    for k, name in enumerate(names):
        assert isinstance(columns[name], np.ndarray)
        assert columns[name].tolist() == [float(r[k]) for r in body], name
        if header[k].endswith("]"):
            assert header[k] == f"{name} [{m.units[name]}]"
        else:
            assert name not in m.units
    assert m.units["time"] == "s" and m.units["block.z"] == "m"
    assert plain(m.last_report) == json.loads(stdout)
    # The motion itself: z(t) = -0.1 + 0.1 cos(ω t), ω = sqrt(k/m) = 20 rad/s; the default
    # integrator ERROR (1e-3) keeps it within 1 % of the 0.1 m amplitude.
    t = columns["time"]
    z = columns["block.z"]
    assert len(t) == 51
    assert np.max(np.abs(z - (-0.1 + 0.1 * np.cos(20.0 * t)))) < 1e-3


@pytest.mark.parametrize("k", [200.0, 800.0, 1250.0, 5000.0])
def test_spring_mass_frequency_follows_sqrt_k_over_m(k):
    m = linkage.load(str(SPRING_MASS))
    m.set("SPRINGDAMPER/1", "K", k)
    modes = m.linear()["modes"]
    assert len(modes) == 1
    # f = sqrt(k/m) / 2π with m = 2 kg; the spring is linear, so only rounding separates them.
    assert modes[0]["frequency"] == pytest.approx(math.sqrt(k / 2.0) / (2 * math.pi), rel=1e-9)


def test_set_means_what_a_command_file_redefinition_means(cli, tmp_path):
    changed = tmp_path / "k3200.adm"
    changed.write_text(SPRING_MASS.read_text().replace("K = 800", "K = 3200"))
    m = linkage.load(str(SPRING_MASS))
    m.set("SPRING/1", "K", 3200)  # the keyword abbreviated as in a dataset
    expected = cli_json(cli, "linear", changed)
    got = plain(m.linear())
    expected.pop("file"), got.pop("file")
    assert got == expected


def test_input_errors_are_exceptions_with_file_line_column(cli, tmp_path):
    bad = tmp_path / "bad.adm"
    bad.write_text(SPRING_MASS.read_text().replace("MASS = 2,", "MASS = two,"))
    code, _, err = cli("verify", bad)
    assert code == 2
    with pytest.raises(linkage.InputError) as caught:
        linkage.load(str(bad)).verify()
    assert isinstance(caught.value, linkage.LinkageError)
    assert caught.value.messages, "messages"
    for message in caught.value.messages:
        assert message.startswith(f"{bad}:17:"), message
        assert message.splitlines()[0] in err
    # A value the model refuses, set from Python: placed at the argument it changes.
    m = linkage.load(str(SPRING_MASS))
    m.set("SPRINGDAMPER/1", "K", -800.0)
    with pytest.raises(linkage.InputError, match=r"spring_mass\.adm:25:\d+: error: .*K must not be negative"):
        m.linear()
    with pytest.raises(linkage.InputError, match="the dataset has no SPRINGDAMPER/7"):
        m.set("SPRINGDAMPER/7", "K", 1.0)
    with pytest.raises(linkage.InputError):
        linkage.load(str(tmp_path / "missing.adm"))


def test_errors_name_keyword_arguments_not_cli_flags():
    m = linkage.load(str(SPRING_MASS))
    with pytest.raises(linkage.InputError) as caught:
        m.simulate(end=1.0, steps=0)
    message = str(caught.value)
    assert "steps must be at least 1" in message, message
    assert "--" not in message, message


def test_a_misspelt_argument_is_an_input_error_unless_read_leniently(tmp_path):
    bad = tmp_path / "masss.adm"
    bad.write_text(SPRING_MASS.read_text().replace("MASS = 2,", "MASSS = 2,"))
    with pytest.raises(linkage.InputError, match=r"unknown argument 'MASSS' of PART \(did you mean MASS\?\)"):
        linkage.load(str(bad))
    # Leniently: read, the argument ignored with a warning (the part has no mass then).
    m = linkage.load(str(bad), lenient_arguments=True)
    warnings = m.verify()["warnings"]
    assert any("unknown argument 'MASSS' of PART ignored" in w for w in warnings), warnings


def test_failed_analyses_raise_analysis_error_with_the_report(cli):
    code, out, _ = cli("ic", DOOR, "--format", "json")
    assert code == 1
    expected = json.loads(out)
    with pytest.raises(linkage.AnalysisError) as caught:
        linkage.load(str(DOOR)).ic()
    assert isinstance(caught.value, linkage.LinkageError)
    assert not isinstance(caught.value, linkage.InputError)
    assert plain(caught.value.report) == expected
    assert str(caught.value) == "\n".join(expected["errors"])


def test_run_acf_equals_linkage_run(cli, tmp_path):
    acf = ROOT / "examples" / "fourbar.acf"
    (tmp_path / "cli").mkdir()
    code, out, err = cli("run", acf, "--out-dir", tmp_path / "cli")
    assert code == 0, err
    summary = linkage.run_acf(str(acf), out_dir=str(tmp_path))
    assert out.splitlines()[0] == f"{summary['commands']} command(s) carried out, {summary['outputs']} output(s)"
    for key in ("msg", "req", "csv"):
        assert Path(summary[key]).is_file(), key
    # No SENSOR's HALT ended the file.
    assert summary["halted"] is None
    assert Path(summary["csv"]).read_text() == (tmp_path / "cli" / Path(summary["csv"]).name).read_text()
    with pytest.raises(linkage.InputError):
        linkage.run_acf(str(tmp_path / "missing.acf"), out_dir=str(tmp_path))


def read_summary(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_sweep_over_k_sharded_equals_whole_and_matches_the_package(cli, tmp_path):
    spec = tmp_path / "sweep.toml"
    spec.write_text(
        f'model = "{SPRING_MASS}"\n[analysis]\nkind = "linear"\n'
        '[[vary]]\nstatement = "SPRINGDAMPER/1"\nargument = "K"\nvalues = [200.0, -5.0, 800.0, 1800.0]\n'
    )
    whole, split = tmp_path / "whole", tmp_path / "split"
    assert cli("sweep", spec, "--out", whole)[0] == 0
    for shard in ("1/2", "2/2"):
        assert cli("sweep", spec, "--out", split, "--shard", shard)[0] == 0
    for d in (whole, split):
        code, _, err = cli("sweep", "merge", d)
        assert code == 0, err
    assert (whole / "summary.csv").read_text() == (split / "summary.csv").read_text()
    rows = read_summary(whole / "summary.csv")
    # The negative rate is refused by the model: recorded as failed, with its message; the
    # runs after it still ran.
    assert rows[1]["status"] == "failed" and rows[1]["exit_code"] == "2"
    assert "K must not be negative" in rows[1]["message"]
    m = linkage.load(str(SPRING_MASS))
    for row in (rows[0], rows[2], rows[3]):
        k = float(row["SPRINGDAMPER/1 K"])
        assert row["status"] == "ok"
        m.set("SPRINGDAMPER/1", "K", k)
        f = m.linear()["modes"][0]["frequency"]
        # The summary writes results to 12 significant digits, like every CSV of linkage.
        assert float(row["frequency_1"]) == pytest.approx(f, rel=1e-11)
        assert f == pytest.approx(math.sqrt(k / 2.0) / (2 * math.pi), rel=1e-9)
