"""FMUs written by `linkage fmu`, imported by FMPy (an independent FMI importer): every FMU
validates (fmpy.validation) and co-simulates.

- tests/fmu/smd_plant.adm (a spring-mass-damper: force in, position out): the step response
  through FMPy against the closed form, for FMI 3.0 and 2.0;
- the same plant closed with a PI controller here, outside the FMU, against linkage's own
  closed-loop run of tests/fmu/smd_pi_closed.adm (the controller as VARIABLE/DIFF);
- a corpus Controls plant (the 3-RPR robot) with constant inputs against `linkage simulate`
  of the dataset with those inputs written into its VARIABLEs;
- a parameter, a saved and restored FMU state, and a failed step (an error status and the
  message in the log, no abort).

The binary is $LINKAGE_BIN, else target/release/linkage, with liblinkage_fmu_binary.so beside it
(both built by `cargo build --release`); without them these tests fail under CI and are
skipped elsewhere, as are the corpus tests without ../shared/corpus.
"""

import csv
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

ROOT = Path(__file__).resolve().parents[2]
PLANT = ROOT / "tests" / "fmu" / "smd_plant.adm"
CLOSED = ROOT / "tests" / "fmu" / "smd_pi_closed.adm"
CORPUS = ROOT.parent / "shared" / "corpus"
RPR = CORPUS / "kiterunner347__3-RPR-parallel--robot__Matlab_Adams__Controls_Plant_2__Controls_Plant_2.adm"
WIPER = CORPUS / "Dinh-Hao-Nguyen__MSCAdams_Wiper_Project__ControlSimulink__Controls_Plant_5.adm"

# smd_plant.adm: m = 2 kg, k = 800 N/m, c = 40 N s/m.
M, K, C = 2.0, 800.0, 40.0


def step_response(force, t, k=K):
    """z(t) of the plant at rest at 0 under a force step at t = 0 (closed form)."""
    w = math.sqrt(k / M)
    zeta = C / (2.0 * math.sqrt(k * M))
    wd = w * math.sqrt(1.0 - zeta * zeta)
    decay = np.exp(-zeta * w * t)
    return force / k * (1.0 - decay * (np.cos(wd * t) + zeta / math.sqrt(1.0 - zeta**2) * np.sin(wd * t)))


@pytest.fixture(scope="module")
def binary():
    path = Path(os.environ.get("LINKAGE_BIN", ROOT / "target" / "release" / "linkage"))
    lib = path.parent / "liblinkage_fmu_binary.so"
    for p in (path, lib):
        if not p.is_file():
            if os.environ.get("CI"):
                pytest.fail(f"{p} is missing under CI (cargo build --release)")
            pytest.skip(f"{p} is missing: build it with cargo build --release")
    return path


@pytest.fixture
def export(binary, tmp_path):
    """`linkage fmu MODEL --out …` (extra arguments passed on); the FMU must validate."""

    def run(model, *args, name="plant.fmu"):
        out = tmp_path / name
        done = subprocess.run(
            [str(binary), "fmu", str(model), "--out", str(out), *map(str, args)],
            capture_output=True,
            text=True,
        )
        assert done.returncode == 0, done.stderr
        assert validate_fmu(str(out)) == []
        return out

    return run


def corpus(path):
    if not path.is_file():
        if os.environ.get("CI"):
            pytest.fail(f"{path} is missing under CI")
        pytest.skip(f"{path} is missing")
    return path


@pytest.mark.parametrize("fmi", ["3", "2"])
def test_fmu_describes_the_pinput_and_poutput_variables_by_name(export, fmi):
    fmu = export(PLANT, "--fmi", fmi, "--parameter", "SPRINGDAMPER/1.K")
    md = read_model_description(str(fmu))
    assert md.fmiVersion == f"{fmi}.0"
    assert md.coSimulation.modelIdentifier == "smd_plant"
    assert md.coSimulation.canGetAndSetFMUstate
    assert not md.coSimulation.canSerializeFMUstate
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["force"].causality == "input"
    assert float(by_name["force"].start) == 0.0
    assert by_name["position"].causality == "output"
    assert by_name["SPRINGDAMPER/1.K"].causality == "parameter"
    assert float(by_name["SPRINGDAMPER/1.K"].start) == K
    assert by_name["initial_static"].type == "Boolean"
    assert [o.variable.name for o in md.outputs] == ["position"]


@pytest.mark.parametrize("fmi", ["3", "2"])
def test_step_response_through_fmpy_equals_the_closed_form(export, fmi):
    fmu = export(PLANT, "--fmi", fmi)
    force = 100.0
    r = simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.01, start_values={"force": force})
    t, z = r["time"], r["position"]
    assert len(t) == 101 and t[-1] == pytest.approx(1.0)
    final = force / K
    # Within 1e-3 of the final value (0.125 m) at every communication point.
    assert np.max(np.abs(z - step_response(force, t))) < 1e-3 * final


def test_a_parameter_set_before_the_initialisation_changes_the_plant(export):
    fmu = export(PLANT, "--parameter", "SPRINGDAMPER/1.K")
    force, k = 100.0, 3200.0
    r = simulate_fmu(
        str(fmu),
        stop_time=0.5,
        output_interval=0.01,
        start_values={"force": force, "SPRINGDAMPER/1.K": k},
    )
    assert np.max(np.abs(r["position"] - step_response(force, r["time"], k))) < 1e-3 * force / k


def test_initial_static_starts_the_plant_at_its_equilibrium_under_the_inputs(export):
    fmu = export(PLANT, "--fmi", "2")
    force = 100.0
    r = simulate_fmu(
        str(fmu),
        stop_time=0.2,
        output_interval=0.01,
        start_values={"force": force, "initial_static": True},
    )
    # At rest at z = F/k from the start (the step response starts at 0 without it).
    assert np.max(np.abs(r["position"] - force / K)) < 1e-6 * force / K


def linkage_csv(binary, model, end, steps, tmp_path):
    out = tmp_path / "run.csv"
    done = subprocess.run(
        [str(binary), "simulate", str(model), "--end", str(end), "--steps", str(steps), "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def slave(fmu, tmp_path, messages=None):
    """An instantiated FMI 3.0 co-simulation slave of `fmu`, its log collected in `messages`."""
    md = read_model_description(str(fmu))
    unzipdir = extract(str(fmu), unzipdir=str(tmp_path / "unzipped"))
    s = FMU3Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="plant",
    )

    def log(env, status, category, message):
        if messages is not None:
            messages.append((status, message.decode()))

    s.instantiate(logMessage=log)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    return s, vrs


def test_pi_loop_closed_outside_the_fmu_equals_linkage_closed_loop(export, binary, tmp_path):
    fmu = export(PLANT)
    s, vr = slave(fmu, tmp_path)
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    # The controller of smd_pi_closed.adm, sampled at each communication point.
    kp, ki, r = 2000.0, 8000.0, 0.05
    h, integral, t = 5e-4, 0.0, 0.0
    fmu_z = {0: s.getFloat64([vr["position"]])[0]}
    for n in range(1, 2001):
        z = s.getFloat64([vr["position"]])[0]
        e = r - z
        s.setFloat64([vr["force"]], [kp * e + ki * integral])
        s.doStep(t, h)
        integral += e * h
        t = n * h
        if n % 20 == 0:
            fmu_z[n // 20] = s.getFloat64([vr["position"]])[0]
    s.terminate()
    s.freeInstance()
    rows = linkage_csv(binary, CLOSED, 1.0, 100, tmp_path)
    own = {i: float(row["REQUEST_1.f2"]) for i, row in enumerate(rows)}
    assert len(own) == 101
    worst = max(abs(fmu_z[i] - own[i]) for i in own)
    # The sampled controller (held over h = 0.5 ms) against the continuous one: within 1 % of
    # the set point over the whole response (measured 0.4 %; 0.8 % with h = 1 ms: the
    # difference is the hold's delay, O(h)).
    assert worst < 1e-2 * r, worst
    assert own[100] == pytest.approx(fmu_z[100], abs=1e-3 * r)


@pytest.mark.parametrize(
    "path, values, tolerance",
    [
        # The 3-RPR robot: three actuator forces in, six positions and velocities out;
        # INTEGRATOR ERROR = 1e-4.
        (RPR, {"VARIABLE/1": 20.0, "VARIABLE/2": -10.0, "VARIABLE/3": 5.0}, 1e-3),
        # The wiper: the motor torque in (N mm), angles and rates out; it has no INTEGRATOR
        # statement (with the default ERROR = 1e-3 restarting every 10 ms or not differs by
        # 2 %), so both runs are given ERROR = 1e-4 (linkage's corrector stops on this model
        # at 1e-5 and below with the torque applied); measured up to 5.6e-3 of the range (the
        # blade angles WL, WR), 1.1e-3 for the motor's.
        (WIPER, {"VARIABLE/32": 1000.0}, 1e-2),
    ],
    ids=["3-RPR", "wiper"],
)
def test_corpus_plant_with_constant_inputs_equals_linkage_simulate(
    export, binary, tmp_path, path, values, tolerance
):
    dataset = corpus(path)
    lines = dataset.read_text(errors="replace").splitlines()
    end = max(i for i, l in enumerate(lines) if l.strip().upper() == "END")
    if not any(l.upper().startswith("INTEGRATOR/") for l in lines):
        lines[end:end] = ["INTEGRATOR/GSTIFF, ERROR = 1E-4"]
        dataset = tmp_path / dataset.name
        dataset.write_text("\n".join(lines) + "\n")
        end += 1
    fmu = export(dataset)
    md = read_model_description(str(fmu))
    inputs = [v for v in md.modelVariables if v.causality == "input"]
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    assert [v.description for v in inputs] == [f"{var}, plant input" for var in values]
    assert len(outputs) >= 3
    start = {v.name: values[v.description.split(",")[0]] for v in inputs}
    r = simulate_fmu(str(fmu), stop_time=0.2, output_interval=0.01, start_values=start)
    # The same dataset with those inputs written into its VARIABLEs, and a REQUEST of the
    # outputs' VARIABLEs (F2, F3, F4, F6, F7, F8 of REQUESTs 9001, …).
    for var, value in values.items():
        at = lines.index(var)
        k = next(i for i in range(at + 1, len(lines)) if lines[i].lstrip(", ").upper().startswith("FUNCTION"))
        lines[k] = f", FUNCTION = {value}"
    ids = [int(v.description.split(",")[0].split("/")[1]) for v in outputs]
    columns, requests = [], []
    for n in range(0, len(ids), 6):
        chunk = ids[n : n + 6]
        rid = 9001 + n // 6
        fields = ["F2", "F3", "F4", "F6", "F7", "F8"][: len(chunk)]
        requests.append(f"REQUEST/{rid}, " + ", ".join(f"{f} = VARVAL({i})" for f, i in zip(fields, chunk)))
        columns += [f"REQUEST_{rid}.{f.lower()}" for f in fields]
    lines[end:end] = requests
    changed = tmp_path / "inputs_written.adm"
    changed.write_text("\n".join(lines) + "\n")
    rows = linkage_csv(binary, changed, 0.2, 20, tmp_path)
    assert len(rows) == len(r) == 21
    for v, col in zip(outputs, columns):
        own = np.array([float(row[col]) for row in rows])
        through_fmu = r[v.name]
        scale = max(np.ptp(own), np.max(np.abs(own)), 1e-9)
        # Both integrate with the dataset's INTEGRATOR; the FMU restarts the integrator at
        # each communication point, so they agree to the integration error.
        assert np.max(np.abs(through_fmu - own)) < tolerance * scale, v.name


def test_a_restored_fmu_state_steps_to_the_same_outputs(export, tmp_path):
    fmu = export(PLANT)
    s, vr = slave(fmu, tmp_path)
    s.enterInitializationMode()
    s.exitInitializationMode()
    s.setFloat64([vr["force"]], [50.0])
    s.doStep(0.0, 0.05)
    state = s.getFMUState()
    s.doStep(0.05, 0.05)
    first = s.getFloat64([vr["position"]])[0]
    s.setFloat64([vr["force"]], [-80.0])
    s.doStep(0.1, 0.05)
    s.setFMUState(state)
    s.doStep(0.05, 0.05)
    again = s.getFloat64([vr["position"]])[0]
    s.freeFMUState(state)
    s.terminate()
    s.freeInstance()
    assert again == pytest.approx(first, rel=1e-12)
    assert first == pytest.approx(step_response(50.0, 0.1), abs=1e-3 * 50.0 / K)


def test_a_failed_step_returns_an_error_status_and_logs_why(export, tmp_path):
    fmu = export(PLANT)
    messages = []
    s, vr = slave(fmu, tmp_path, messages)
    s.enterInitializationMode()
    s.exitInitializationMode()
    s.doStep(0.0, 0.01)
    s.setFloat64([vr["force"]], [float("nan")])
    with pytest.raises(FMICallException) as failed:
        s.doStep(0.01, 0.01)
    assert failed.value.status == 3  # fmi3Error
    assert any(status == 3 for status, _ in messages), messages
    # After the error the instance refuses steps (with an error, not an abort) until reset.
    with pytest.raises(FMICallException):
        s.doStep(0.02, 0.01)
    s.reset()
    s.enterInitializationMode()
    s.exitInitializationMode()
    s.doStep(0.0, 0.01)
    s.freeInstance()


def test_python_export_equals_the_cli_export(export, binary, tmp_path):
    if os.environ.get("CI"):
        import linkage
    else:
        linkage = pytest.importorskip("linkage")
    cli_fmu = export(PLANT, "--fmi", "2", "--parameter", "SPRINGDAMPER/1.K")
    out = tmp_path / "python.fmu"
    done = linkage.export_fmu(
        str(PLANT),
        str(out),
        fmi=2,
        parameters=["SPRINGDAMPER/1.K"],
        binary=str(binary.parent / "liblinkage_fmu_binary.so"),
    )
    assert done["model_identifier"] == "smd_plant"
    assert (done["inputs"], done["outputs"]) == (["force"], ["position"])
    assert done["parameters"] == ["SPRINGDAMPER/1.K"]
    assert out.read_bytes() == cli_fmu.read_bytes()
    with pytest.raises(linkage.InputError, match="no PINPUT and no POUTPUT"):
        linkage.export_fmu(str(ROOT / "examples" / "spring_mass.adm"), str(tmp_path / "x.fmu"))
