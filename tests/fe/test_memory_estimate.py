"""Memory estimate before a reduction: METIS fill from the analysis phase, the plan, the
refusal with the figure, and the estimate against a measured peak."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import scipy.sparse as sp

from flexarm.fe import MATERIALS, TetMesh, assemble
from flexarm.fe.memory_estimate import (
    GB,
    InsufficientMemoryError,
    available_memory,
    estimate_memory,
    plan_memory,
)
from flexarm.fe.solvers import available_backends, factor_size

needs_pardiso = pytest.mark.skipif("pardiso" not in available_backends(),
                                   reason="PARDISO (pypardiso/MKL) not installed")


@needs_pardiso
def test_factor_size_dense_and_chain():
    n = 40
    dense = factor_size(sp.csr_matrix(np.ones((n, n)) + n * np.eye(n)))
    # no sparsity to exploit: L, stored as one square supernode
    assert n * (n + 1) // 2 <= dense.factor_entries <= n * n + n
    chain = factor_size(sp.diags([-1.0, 4.0, -1.0], [-1, 0, 1], shape=(4000, 4000)).tocsr())
    assert 2 * 4000 - 1 <= chain.factor_entries <= 3 * 4000  # no fill beyond the band


@needs_pardiso
def test_node_graph_fill_matches_dof_level_analysis():
    # The estimate analyses the node graph (1/9 of the entries); the DOF-level analysis
    # of the assembled K is the reference.
    mesh = TetMesh.box((1.0, 0.2, 0.15), (16, 4, 3), order=2)
    K, _ = assemble(mesh, MATERIALS["steel"])
    ref = factor_size(K).factor_entries
    est = estimate_memory(mesh, analyse=True)
    assert est.method == "analysis"
    assert 0.9 < est.factor_entries / ref < 1.15


def test_bound_is_above_the_analysis():
    mesh = TetMesh.box((1.0, 0.2, 0.15), (16, 4, 3), order=2)
    bound = estimate_memory(mesh, analyse=False)
    assert bound.method == "bound"
    if "pardiso" in available_backends():
        assert bound.factor_entries > estimate_memory(mesh, analyse=True).factor_entries


def test_plan_picks_in_core_or_refuses_with_the_figure():
    mesh = TetMesh.box((1.0, 0.1, 0.1), (20, 2, 2), order=2)
    plan = plan_memory(mesh, 10, available=8 * GB)
    assert (plan.path, plan.backend, plan.ranks) == ("in-core", None, 1)
    # near the limit the plan asks METIS (the bound alone is generous)
    need = estimate_memory(mesh, 10 + 12, analyse=True).total_bytes
    assert plan_memory(mesh, 10, available=1.01 * need).path == "in-core"
    with pytest.raises(InsufficientMemoryError) as exc:
        plan_memory(mesh, 10, available=0.99 * need, precision="double")
    msg = str(exc.value)
    assert f"{mesh.n_dofs} DOF" in msg and f"{need / GB:.3g} GB" in msg
    assert "mpiexec --hostfile" in msg and "--backend petsc" in msg
    assert "\n" not in msg


def test_plan_falls_back_to_a_single_precision_factor():
    mesh = TetMesh.box((1.0, 0.1, 0.1), (20, 2, 2), order=2)
    est = estimate_memory(mesh, 10 + 12, analyse=True)
    single = est.in_precision("single")
    # the factor's values take half the bytes, and less goes to its indices
    assert single.factor_bytes <= 0.5 * est.factor_bytes
    assert single.factor_entries == est.factor_entries
    assert single.total_bytes < est.total_bytes
    between = 0.5 * (single.total_bytes + est.total_bytes)
    plan = plan_memory(mesh, 10, available=between)
    assert (plan.path, plan.precision, plan.backend) == ("in-core", "single", None)
    assert plan.estimate.total_bytes == pytest.approx(single.total_bytes)
    assert plan_memory(mesh, 10, available=1.01 * est.total_bytes).precision == "double"
    # asked for explicitly, single precision is used even where double fits
    assert plan_memory(mesh, 10, available=8 * GB, precision="single").precision == "single"
    # nothing fits: one line with both figures
    with pytest.raises(InsufficientMemoryError) as exc:
        plan_memory(mesh, 10, available=0.99 * single.total_bytes)
    msg = str(exc.value)
    assert f"{est.total_bytes / GB:.3g} GB in core" in msg
    assert f"{single.total_bytes / GB:.3g} GB with a single-precision factor" in msg
    with pytest.raises(InsufficientMemoryError, match="in core with a single-precision factor"):
        plan_memory(mesh, 10, available=0.99 * single.total_bytes, precision="single")
    # CHOLMOD has no single-precision factor: no fallback
    with pytest.raises(InsufficientMemoryError):
        plan_memory(mesh, 10, backend="cholmod", available=between)
    with pytest.raises(ValueError, match="PETSc backend factorises in double"):
        plan_memory(mesh, 10, backend="petsc", precision="single")


def test_petsc_plan_checks_the_share_of_this_host():
    mesh = TetMesh.box((1.0, 0.1, 0.1), (20, 2, 2), order=2)
    plan = plan_memory(mesh, 10, backend="petsc", available=8 * GB)
    assert (plan.path, plan.backend) == ("petsc", "petsc")
    with pytest.raises(InsufficientMemoryError, match="on PETSc with 1 rank"):
        plan_memory(mesh, 10, backend="petsc", available=1e5)


def test_reduction_refuses_before_assembling(monkeypatch):
    from flexarm.reduction.interfaces import CylinderRegion
    from flexarm.reduction.reduce import reduce_with_stats

    calls = []
    monkeypatch.setattr("flexarm.reduction.reduce.coupled_model",
                        lambda *a, **k: calls.append(a))
    monkeypatch.setenv("FLEXARM_MEMORY_GB", "1e-6")
    assert available_memory() == pytest.approx(1e-6 * GB)
    mesh = TetMesh.box((1.0, 0.1, 0.1), (8, 1, 1))
    ends = [CylinderRegion(n, (x, .05, .05), (1, 0, 0), 0, 1, 1e-3)
            for n, x in (("a", 0.0), ("b", 1.0))]
    with pytest.raises(InsufficientMemoryError, match="available on this machine"):
        reduce_with_stats(mesh, MATERIALS["steel"], ends, "rbe2", "cb", 4)
    assert calls == []


_MEASURE = """
import json, re
from flexarm.fe import MATERIALS
from flexarm.reduction.reduce import reduce_with_stats
from flexarm.studies.part_study import bar_link

def rss(field):
    text = open("/proc/self/status").read()
    return int(re.search(field + r":\\s+(\\d+) kB", text)[1]) * 1024

mesh, regions = bar_link(1.0, 0.12, (40, 5, 5), order=2)
open("/proc/self/clear_refs", "w").write("5")  # the peak (VmHWM) restarts from now
base = rss("VmRSS")
reduce_with_stats(mesh, MATERIALS["steel"], regions, "rbe2", "cb", 20, backend="pardiso",
                  precision=PRECISION)
print(json.dumps({"growth": rss("VmHWM") - base}))
"""


@needs_pardiso
@pytest.mark.parametrize("precision", ["double", "single"])
def test_estimate_bounds_the_measured_peak(precision):
    # A fresh process that only reduces, so its peak belongs to this reduction alone
    # (29k-DOF Tet10 link); the estimate (whose own analysis allocates) is made here.
    from flexarm.studies.part_study import bar_link

    mesh, _ = bar_link(1.0, 0.12, (40, 5, 5), order=2)
    estimate = estimate_memory(mesh, 12 + 20, analyse=True).in_precision(precision).total_bytes
    code = f"PRECISION = {precision!r}\n" + _MEASURE
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    got = json.loads(run.stdout.strip().splitlines()[-1])
    got["estimate"] = estimate
    assert got["growth"] <= got["estimate"] <= 2.0 * got["growth"], got


def test_the_refusal_asks_for_the_fewest_machines_whose_share_fits():
    """One rank per machine: the hint names the smallest N whose per-rank estimate fits
    the memory here, and says so when no number of machines would (the share every rank
    keeps bounds it from below)."""
    mesh = TetMesh.box((1.0, 0.1, 0.1), (20, 2, 2), order=2)
    est = estimate_memory(mesh, 10 + 12, analyse=True)
    per_rank = [est.per_rank_bytes(n) for n in range(1, 9)]
    assert all(np.diff(per_rank) < 0)  # more machines, less each
    assert per_rank[1] > 0.5 * per_rank[0]  # ... but not an even split
    for n in (2, 3, 5):
        avail = 0.5 * (per_rank[n - 1] + per_rank[n - 2])  # fits n ranks, not n - 1
        with pytest.raises(InsufficientMemoryError, match=f"-n {n} --map-by node"):
            plan_memory(mesh, 10, available=avail, precision="double")
    with pytest.raises(InsufficientMemoryError, match="even 64 machines like this one"):
        plan_memory(mesh, 10, available=0.9 * est.per_rank_bytes(64), precision="double")
