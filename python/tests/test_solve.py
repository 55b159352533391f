"""seam.solve solves a case as `seam solve` does: the same files, bit for bit.

The case and its meshes are those of `seam example warped-glue` (glue) and
`seam example bulging-contact` (contact), made small; the reference files are
those the `seam` binary that `cargo test` builds (target/debug/seam, or
$SEAM_BIN) writes.
"""

import json
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

import seam

tomllib = pytest.importorskip("tomllib")  # Python 3.11+

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tests" / "python"))
from seam_cli import seam as run_cli  # noqa: E402

EXAMPLES = {
    "warped-glue": ["--slave-cells", "2", "--ratio", "2"],
    "bulging-contact": ["--slave-cells", "4"],
}


@pytest.fixture(params=sorted(EXAMPLES))
def example(request, tmp_path):
    """An example's case (with its meshes) and the files `seam solve` wrote."""
    name = request.param
    done = run_cli("example", name, "-o", "ex", *EXAMPLES[name], cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    return tmp_path / "ex"


def without_paths_and_times(summary):
    s = dict(summary)
    for key in ("seconds", "case", "output_dir"):
        s.pop(key)
    s["bodies"] = [{k: v for k, v in b.items() if k != "mesh"} for b in s["bodies"]]
    return s


def test_written_files_are_those_of_seam_solve(example, tmp_path):
    solution = seam.solve(example / "case.toml", threads=1)
    written = solution.write(tmp_path / "py")
    cli = sorted(p.name for p in (example / "out").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == cli
    for name in cli:
        a, b = (example / "out" / name).read_bytes(), (tmp_path / "py" / name).read_bytes()
        if name == "summary.json":
            a, b = json.loads(a), json.loads(b)
            assert b == written
            a["threads"] = b["threads"]
            assert without_paths_and_times(a) == without_paths_and_times(b)
            assert b["output_dir"] == str(tmp_path / "py")
        else:
            assert a == b, name
    assert without_paths_and_times(solution.summary) == without_paths_and_times(written)


def test_bodies_and_interfaces_are_those_of_the_files(example):
    solution = seam.solve(str(example / "case.toml"))
    summary = solution.summary
    assert list(solution.bodies) == [b["name"] for b in summary["bodies"]]
    for b in summary["bodies"]:
        body = solution.bodies[b["name"]]
        vtu = meshio.read(example / "out" / b["file"])
        np.testing.assert_array_equal(body.points, vtu.points)
        np.testing.assert_array_equal(body.displacement, vtu.point_data["displacement"])
        cells = sum(len(c.data) for c in vtu.cells)
        assert body.stress.shape == (cells, 6) and body.von_mises.shape == (cells,)
        np.testing.assert_array_equal(body.von_mises, np.concatenate(vtu.cell_data["von_mises"]))
        assert np.max(np.linalg.norm(body.displacement, axis=1)) == b["max_displacement"]
    assert len(solution.interfaces) == len(summary["interfaces"])
    for f, s in zip(solution.interfaces, summary["interfaces"]):
        assert (f.master, f.slave, f.kind) == (s["master"], s["slave"], s["kind"])
        vtu = meshio.read(example / "out" / s["file"])
        names = ["traction", "normal_traction"]
        if f.kind == "contact":
            names += ["contact_pressure", "gap", "active"]
        for name in names:
            np.testing.assert_array_equal(getattr(f, name), vtu.point_data[name])


def test_a_dict_case_is_the_file_case(example, monkeypatch):
    monkeypatch.chdir(example)
    case = tomllib.loads((example / "case.toml").read_text())
    from_dict = seam.solve(case)
    from_file = seam.solve("case.toml")
    a, b = from_dict.summary, from_file.summary
    assert b["case"] == "case.toml" and a["case"] == "<case dict>"
    assert without_paths_and_times(a) == without_paths_and_times(b)
    for name, body in from_file.bodies.items():
        np.testing.assert_array_equal(from_dict.bodies[name].displacement, body.displacement)


def test_errors_are_the_one_line_messages_of_seam_solve(example, tmp_path):
    text = (example / "case.toml").read_text()
    missing = tmp_path / "missing.toml"
    missing.write_text(text.replace("lower.msh", "nowhere.msh"))
    with pytest.raises(seam.CaseError) as e:
        seam.solve(missing)
    cli = run_cli("solve", missing, cwd=tmp_path)
    assert cli.returncode == 2
    assert cli.stderr == f"seam: error: {e.value}\n"
    assert "nowhere.msh" in str(e.value) and "\n" not in str(e.value)

    bad = tmp_path / "bad.toml"
    bad.write_text("not_a_key = 1\n" + text)
    with pytest.raises(seam.CaseError) as e:
        seam.solve(bad)
    cli = run_cli("solve", bad, cwd=tmp_path)
    assert cli.returncode == 2 and cli.stderr == f"seam: error: {e.value}\n"
    assert "not_a_key" in str(e.value)

    with pytest.raises(seam.CaseError, match="not_a_key"):
        seam.solve({**tomllib.loads(text), "not_a_key": 1})


def test_failures_are_classed_as_seam_solve_s_exit_codes(tmp_path):
    """CaseError, NoCouplingError and ConvergenceError are SolveErrors, as the
    CLI's exit codes 2, 1 and 2 sort the same failures."""
    assert all(issubclass(c, seam.SolveError) for c in (seam.CaseError, seam.NoCouplingError, seam.ConvergenceError))
    cases = {}
    for name, args in EXAMPLES.items():
        done = run_cli("example", name, "-o", name, *args, cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        cases[name] = (tmp_path / name / "case.toml").read_text()
    glue = cases["warped-glue"]
    # The slave surface 1/2 away from the master's: nothing pairs within max_gap.
    apart = tmp_path / "warped-glue" / "apart.toml"
    apart.write_text(glue.replace('master = "lower:top"', 'master = "lower:bottom"\nmax_gap = 0.01'))
    with pytest.raises(seam.NoCouplingError, match="lower:bottom") as e:
        seam.solve(apart)
    cli = run_cli("solve", apart, "--force", cwd=tmp_path)
    assert cli.returncode == 1 and cli.stderr == f"seam: {e.value}\n", cli.stderr
    # An interface naming a body the case does not have.
    case = tomllib.loads(glue)
    case["body"] = [{**b, "mesh": str(tmp_path / "warped-glue" / b["mesh"])} for b in case["body"] if b["name"] == "lower"]
    with pytest.raises(seam.CaseError, match="upper"):
        seam.solve(case)
    # The active set of contact capped at one step.
    capped = tmp_path / "bulging-contact" / "capped.toml"
    capped.write_text(cases["bulging-contact"] + "\n[contact]\nmax_iterations = 1\n")
    with pytest.raises(seam.ConvergenceError, match="did not settle in 1 steps") as e:
        seam.solve(capped)
    cli = run_cli("solve", capped, "--force", cwd=tmp_path)
    assert cli.returncode == 2 and cli.stderr == f"seam: error: {e.value}\n", cli.stderr


def test_rtol_is_that_of_seam_solve(example, tmp_path):
    """rtol is PCG's tolerance: the same answer as `seam solve --rtol`, and a
    value outside (0, 1), or below what double precision reaches, is refused."""
    solution = seam.solve(example / "case.toml", solver="pcg", rtol=1e-12)
    cli = run_cli("solve", example / "case.toml", "--solver", "pcg", "--rtol", "1e-12", "--force", cwd=tmp_path)
    assert cli.returncode == 0, cli.stderr
    written = json.loads((example / "out" / "summary.json").read_text())
    assert without_paths_and_times(solution.summary) == without_paths_and_times(written)
    with pytest.raises(seam.CaseError, match=r"rtol 2(\.0)? must lie in \(0, 1\)"):
        seam.solve(example / "case.toml", solver="pcg", rtol=2.0)
    with pytest.raises(seam.SolveError, match=r"^rtol 1e-300 is below what double precision can reach: .*use 1e-14"):
        seam.solve(example / "case.toml", solver="pcg", rtol=1e-300)


def test_write_recovers_what_an_interrupted_run_left_with_one_warning(example, tmp_path):
    solution = seam.solve(example / "case.toml")
    out = tmp_path / "out"
    solution.write(out)
    written = sorted(p.name for p in out.iterdir())
    # What a killed run leaves: a temporary file, a write probe, its lock file.
    (out / ".summary.json.seam-99999.partial").write_text("half")
    (out / ".seam-write-probe-99999").write_text("")
    (out / ".seam.lock").write_text("99999\n")
    with pytest.warns(seam.OutputWarning) as heard:
        solution.write(out, force=True)
    assert [str(w.message) for w in heard] == [
        f"recovered {out}: 2 leftover files of interrupted runs removed"
    ]
    assert sorted(p.name for p in out.iterdir()) == written


def test_write_refuses_existing_files_without_force(example, tmp_path):
    solution = seam.solve(example / "case.toml")
    solution.write(tmp_path / "out")
    with pytest.raises(seam.SolveError, match="already exists; pass --force") as e:
        solution.write(tmp_path / "out")
    assert type(e.value) is seam.SolveError
    solution.write(tmp_path / "out", force=True)
    with pytest.raises(ValueError, match="solver"):
        seam.solve(example / "case.toml", solver="lu")


def test_load_steps_are_solutions_and_files(example, monkeypatch, tmp_path):
    """`[load]` in a case dict: `Solution.steps` holds every step (the last
    the final state), and `write` adds steps/ and a ParaView collection per
    body and interface that lists them at their times."""
    import xml.etree.ElementTree as ET

    monkeypatch.chdir(example)
    case = tomllib.loads((example / "case.toml").read_text())
    case["load"] = {"times": [0.4, 0.7, 1.0]}
    solution = seam.solve(case)
    steps = solution.steps
    assert [s.time for s in steps] == [0.4, 0.7, 1.0]
    assert [s.summary["time"] for s in steps] == [0.4, 0.7, 1.0]
    assert solution.summary["load"] == {"steps": 3, "times": [0.4, 0.7, 1.0]}
    for name, body in solution.bodies.items():
        np.testing.assert_array_equal(steps[-1].bodies[name].displacement, body.displacement)
        assert not np.array_equal(steps[0].bodies[name].displacement, body.displacement)
    out = tmp_path / "out"
    solution.write(out)
    names = [b["file"][: -len(".vtu")] for b in solution.summary["bodies"]]
    names += [f["file"][: -len(".vtu")] for f in solution.summary["interfaces"]]
    for name in names:
        datasets = ET.parse(out / f"{name}.pvd").getroot().find("Collection").findall("DataSet")
        assert [float(d.get("timestep")) for d in datasets] == [0.4, 0.7, 1.0]
        assert [d.get("file") for d in datasets] == [f"steps/{name}_{k:04d}.vtu" for k in (1, 2, 3)]
        # The final state's file is the last step's.
        assert (out / f"{name}.vtu").read_bytes() == (out / f"steps/{name}_0003.vtu").read_bytes()
    for k, step in enumerate(steps, start=1):
        for name, body in step.bodies.items():
            vtu = meshio.read(out / "steps" / f"{name}_{k:04d}.vtu")
            np.testing.assert_array_equal(body.displacement, vtu.point_data["displacement"])
        for f, s in zip(step.interfaces, solution.summary["interfaces"]):
            vtu = meshio.read(out / "steps" / f"{s['file'][:-4]}_{k:04d}.vtu")
            np.testing.assert_array_equal(f.traction, vtu.point_data["traction"])


def test_hyperelastic_bodies_in_a_case_dict(tmp_path, monkeypatch):
    """`material = "neo-hookean"` on every body of the warped-glue example
    (dual multipliers, two load steps): each step is Newton's, with its
    residuals and line search in the summary; under the example's small load
    (strains of 1e-3) the displacements are the linear ones to 1 %; a linear
    body among hyperelastic ones is refused naming both."""
    done = run_cli("example", "warped-glue", "-o", "ex", *EXAMPLES["warped-glue"], cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    monkeypatch.chdir(tmp_path / "ex")
    case = tomllib.loads(Path("case.toml").read_text())
    for f in case["interface"]:
        f["multiplier"] = "dual"
    linear = seam.solve(case)
    finite = {**case, "load": {"steps": 2}, "body": [{**b, "material": "neo-hookean"} for b in case["body"]]}
    solution = seam.solve(finite)
    assert len(solution.steps) == 2
    for step in solution.summary["steps"]:
        assert step["iterations"] == len(step["residuals"]) == len(step["line_search"]) >= 1
        assert step["residuals"][-1] <= 1e-10
    for name, body in solution.bodies.items():
        u, v = body.displacement, linear.bodies[name].displacement
        assert np.abs(u - v).max() <= 1e-2 * np.abs(v).max(), name
    mixed = {**finite, "body": [finite["body"][0], case["body"][1]]}
    with pytest.raises(seam.CaseError, match='is linear and body ".*" hyperelastic'):
        seam.solve(mixed)


def test_hyperelastic_contact_with_friction_in_a_case_dict(tmp_path, monkeypatch):
    """The ironing example's case with friction (coarse) as a dict: every
    load step converged by Newton in one part, the contact force of each
    step in the summary (`forces`), and in each step's interface Coulomb's
    law at the slipping points (|t_τ| = μ p) and the accumulated slip."""
    done = run_cli("example", "ironing", "-o", "ex", "--slave-cells", "2", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    monkeypatch.chdir(tmp_path / "ex" / "friction")
    case = tomllib.loads(Path("case.toml").read_text())
    assert all(b["material"] == "neo-hookean" for b in case["body"])
    solution = seam.solve(case)
    assert len(solution.steps) == 20
    for k, step in enumerate(solution.summary["steps"]):
        assert step["residuals"][-1] <= 1e-10 and step["substeps"] >= 1
        f = step["forces"][0]
        assert f[2] > 0, f
        interface = solution.steps[k].interfaces[0]
        active, stick = interface.active > 0, interface.stick > 0
        slip = active & ~stick
        pressure = interface.contact_pressure[slip]
        tangential = np.linalg.norm(interface.tangential_traction[slip], axis=1)
        np.testing.assert_allclose(tangential, 0.3 * pressure, rtol=1e-8, atol=1e-10 * pressure.max(initial=1.0))
    last = solution.steps[-1].interfaces[0]
    assert np.all(last.slip[last.active > 0][:, 0] > 2.0)
