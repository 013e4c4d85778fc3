# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: sparse direct backends on one clamped link, factorisation and 20 modes.

For each backend (``pardiso``, ``splu``, ``cholmod`` when scikit-sparse imports) and
eigen method, a subprocess assembles the same K, M (so the threading environment is set
before any BLAS loads), eliminates the clamped DOFs and times, best of ``--repeat``:

* the factorisation of K_ff (SPD); ``first`` is the first call in the fresh process
  (MKL's lazy start included), the others reuse nothing but the loaded library;
* one solve, 20 right-hand sides in one call, and 20 one-by-one;
* ``modes(K, M, n=20, eigensolver=shift_invert(0.0, backend, method=...))``:
  factorisation plus the shift-invert eigen-solve, wall and CPU time (user + system of
  the worker, all threads), with the number of solves (right-hand sides).

``splu (scipy default) + ARPACK`` is plain ``scipy.sparse.linalg.splu(K)`` (COLAMD,
partial pivoting: what a user gets without options) under SciPy's ``eigsh``: the
baseline of the issue's target.  ``x base`` columns are ratios to it, measured in the
same run; ``method`` is ``block`` (flexarm's default eigensolver) or ``arpack``.
``splu (ours: symmetric)`` is SuperLU as an expert configures it for a symmetric
matrix (``permc_spec="MMD_AT_PLUS_A"``, ``SymmetricMode``, no off-diagonal pivoting).
``pardiso single`` factorises in single precision and refines every solve to double
accuracy (half the factor's memory).

The expert's alternative for the eigen-solve is SLEPc: Krylov-Schur, shift-and-invert at
0 with a Cholesky factor from MUMPS or CHOLMOD (PETSc's own builds), tolerance 1e-12,
run with the MPI environment's interpreter (``.venv/mpi``, ``bash install.sh --mpi``) on
the same K, M, in its own process.  ``x slepc`` is the SLEPc + CHOLMOD time over ours;
``solves/k`` is the distance to the eigen-solve's bound: right-hand sides solved per
mode found (1 is the floor of any shift-invert method that finds each mode with one
solve).

    python benchmarks/solvers.py            # clamped Tet4 link, ~66k DOF
    python benchmarks/solvers.py --tet10    # also the Tet10 version of the same link
    python benchmarks/solvers.py --quick    # small box, seconds
    python benchmarks/solvers.py --bar 88x9x9   # the 191k-DOF Tet10 bar of reduction.py
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

MPI_PYTHON = os.environ.get("FLEXARM_MPI_PYTHON", os.path.join(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))), ".venv", "mpi", "bin", "python"))
#: SLEPc's relative residual tolerance (the frequencies then match ours to ~1e-12).
SLEPC_TOL = 1e-12

#: fTetWild edge of the solver link [m]: 76k Tet4, 68k DOF (66k free), like DESIGN §10.
SOLVER_LINK_SIZE = 0.011
#: Clamp the nodes within this fraction of the part's length from its low end.
CLAMP_FRACTION = 0.02


def problem(quick: bool, order: int, bar: str | None = None):
    """(K_ff, M_ff, description) of the clamped link (or a clamped box when ``quick``, or
    the Tet10 bar of ``reduction.py`` with ``bar`` cells, e.g. ``88x9x9``: 191,691 DOF)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from assembly import link_mesh, perturbed_box

    from flexarm.fe import MATERIALS, assemble, dof_split, node_dofs

    if bar:
        from flexarm.studies.part_study import bar_link

        div = tuple(int(v) for v in bar.split("x"))
        mesh, _ = bar_link(1.0, 0.12, div, order=2)
        found = (mesh, f"Tet10 bar 1.0 x 0.12 x 0.12 m, {bar} cells")
        order = 1  # already Tet10
    else:
        found = None if quick else link_mesh(allow_meshing=True, size=SOLVER_LINK_SIZE)
    mesh, what = found if found else perturbed_box(6_000 if quick else 100_000)
    if order == 2:
        mesh = mesh.to_tet10()
    lo, hi = mesh.bounds()
    axis = int(np.argmax(hi - lo))
    fixed = np.flatnonzero(mesh.points[:, axis] <= lo[axis] + CLAMP_FRACTION * (hi - lo)[axis])
    K, M = assemble(mesh, MATERIALS["steel"])
    split = dof_split(mesh.n_dofs, node_dofs(fixed))
    what = (f"{what}, Tet{4 if mesh.order == 1 else 10}, {mesh.n_tets} tets, "
            f"{len(fixed)} clamped nodes")
    return split.condense(K), split.condense(M), what


def _factor(K, backend: str):
    """Our factorisation, or plain ``scipy.sparse.linalg.splu(K)`` (COLAMD, partial
    pivoting: what a user gets without options) for ``splu-scipy-default``."""
    from flexarm.fe import Factor, factorize

    if backend == "pardiso-single":
        return factorize(K, backend="pardiso", spd=True, precision="single")
    if backend != "splu-scipy-default":
        return factorize(K, backend=backend, spd=True)
    import scipy.sparse.linalg as spla

    t = time.perf_counter()
    lu = spla.splu(K.tocsc())
    return Factor(K.shape[0], backend, time.perf_counter() - t, lu.solve)


def _cpu() -> float:
    """User + system time of this process [s], all threads."""
    t = os.times()
    return t.user + t.system


def worker(args) -> None:
    from flexarm.fe import modes, shift_invert

    Kf, Mf, what = problem(args.quick, args.order, args.bar)
    rng = np.random.default_rng(0)
    B = rng.standard_normal((Kf.shape[0], 20))
    out = {"what": what, "n": Kf.shape[0], "nnz": Kf.nnz}

    # Best of --repeat: the first call in a fresh process also loads MKL and starts its
    # thread pool (a one-off per process, reported separately as factor_first).
    times = []
    for _ in range(max(args.repeat, 1)):
        t = time.perf_counter()
        f = _factor(Kf, args.backend)
        times.append(time.perf_counter() - t)
    out["factor_first"] = times[0]
    out["factor"] = min(times)
    t = time.perf_counter()
    f.solve(B[:, 0])
    out["solve1"] = time.perf_counter() - t
    t = time.perf_counter()
    X = f.solve(B)
    out["solve20_block"] = time.perf_counter() - t
    t = time.perf_counter()
    Y = np.column_stack([f.solve(B[:, j]) for j in range(20)])
    out["solve20_loop"] = time.perf_counter() - t
    out["residual"] = float(np.abs(Kf @ X - B).max() / np.abs(B).max())
    out["block_vs_loop"] = float(np.abs(X - Y).max() / np.abs(Y).max())
    del f

    # shift 0 (clamped part): the eigensolver factorises K itself, as a user's call
    # would (the SciPy baseline gets its plain splu factor passed in, timed with it);
    # the solves are counted (right-hand sides) through the factor's solve function
    import flexarm.fe.eigen as eigen_module

    count = [0]

    def counted(f):
        inner = f._solve

        def solve(b):
            count[0] += 1 if b.ndim == 1 else b.shape[1]
            return inner(b)

        f._solve = solve
        return f

    original = eigen_module.factorize
    eigen_module.factorize = lambda *a, **kw: counted(original(*a, **kw))
    baseline = args.backend == "splu-scipy-default"
    single = args.backend == "pardiso-single"
    solver = shift_invert(0.0, backend=None if baseline else args.backend.split("-")[0],
                          method=args.method, precision="single" if single else "double")
    best = None
    try:
        for _ in range(max(args.repeat, 1)):
            count[0] = 0
            t, c = time.perf_counter(), _cpu()
            factor = counted(_factor(Kf, args.backend)) if baseline else None
            m = modes(Kf, Mf, n=20, eigensolver=solver, factor=factor)
            run = (time.perf_counter() - t, _cpu() - c, count[0])
            best = run if best is None or run[0] < best[0] else best
    finally:
        eigen_module.factorize = original
    out["eigen"], out["eigen_cpu"], out["eigen_solves"] = best
    out["freq_hz"] = m.freq_hz.tolist()
    print(json.dumps(out))


def dump(args) -> None:
    """Write the problem's K_ff, M_ff for the SLEPc peer (another interpreter)."""
    import scipy.sparse as sp

    Kf, Mf, what = problem(args.quick, args.order, args.bar)
    sp.save_npz(os.path.join(args.dump, "K.npz"), Kf.tocsr())
    sp.save_npz(os.path.join(args.dump, "M.npz"), Mf.tocsr())
    print(json.dumps({"what": what, "n": Kf.shape[0], "nnz": Kf.nnz}))


def slepc_worker(args) -> None:
    """SLEPc Krylov-Schur shift-invert at 0, Cholesky by ``args.slepc`` (in .venv/mpi)."""
    import scipy.sparse as sp
    from petsc4py import PETSc
    from slepc4py import SLEPc

    PETSc.Log.begin()  # counts MatSolve calls: the solves of the spectral transform
    mats = []
    for name in ("K", "M"):
        A = sp.load_npz(os.path.join(args.dump, f"{name}.npz")).tocsr()
        m = PETSc.Mat().createAIJ(size=A.shape, csr=(A.indptr.astype(PETSc.IntType),
                                  A.indices.astype(PETSc.IntType), A.data), comm=PETSc.COMM_SELF)
        m.setOption(PETSc.Mat.Option.SYMMETRIC, True)
        m.setOption(PETSc.Mat.Option.SPD, True)
        m.assemble()
        mats.append(m)
    event, best = PETSc.Log.Event("MatSolve"), None
    for _ in range(max(args.repeat, 1)):
        c0, t, c = event.getPerfInfo()["count"], time.perf_counter(), _cpu()
        eps = SLEPc.EPS().create(PETSc.COMM_SELF)
        eps.setOperators(*mats)
        eps.setProblemType(SLEPc.EPS.ProblemType.GHEP)
        eps.setDimensions(20)
        eps.setTarget(0.0)
        eps.setWhichEigenpairs(SLEPc.EPS.Which.TARGET_MAGNITUDE)
        st = eps.getST()
        st.setType("sinvert")
        ksp = st.getKSP()
        ksp.setType("preonly")
        ksp.getPC().setType("cholesky")
        ksp.getPC().setFactorSolverType(args.slepc)
        eps.setTolerances(SLEPC_TOL, 1000)
        eps.solve()
        run = (time.perf_counter() - t, _cpu() - c, event.getPerfInfo()["count"] - c0)
        best = run if best is None or run[0] < best[0] else best
        w = np.sort([eps.getEigenvalue(i).real for i in range(min(eps.getConverged(), 20))])
        eps.destroy()
    print(json.dumps({"eigen": best[0], "eigen_cpu": best[1], "eigen_solves": int(best[2]),
                      "freq_hz": (np.sqrt(np.clip(w, 0, None)) / (2 * np.pi)).tolist()}))


def run_slepc(args, order: int, solver: str) -> dict | None:
    """The SLEPc peer on this order's matrices, or None (with the reason printed)."""
    import tempfile

    if not os.path.exists(MPI_PYTHON):
        print(f"SLEPc + {solver}: skipped ({MPI_PYTHON} missing: bash install.sh --mpi)")
        return None
    with tempfile.TemporaryDirectory() as tmp:
        common = ["--order", str(order), "--repeat", str(args.repeat), "--dump", tmp] + (
            ["--quick"] if args.quick else []) + (["--bar", args.bar] if args.bar else [])
        made = subprocess.run([sys.executable, __file__, *common], capture_output=True,
                              text=True, check=False)
        res = subprocess.run([MPI_PYTHON, __file__, *common, "--slepc", solver],
                             capture_output=True, text=True, check=False) \
            if made.returncode == 0 else made
    if res.returncode != 0:
        print(f"SLEPc + {solver}: failed: {res.stderr.strip().splitlines()[-1:]}")
        return None
    return json.loads(res.stdout.strip().splitlines()[-1])


VARIANTS = [
    # (label, backend, eigen method, environment); the last one is the baseline
    ("pardiso", "pardiso", "block", {}),
    ("pardiso + ARPACK", "pardiso", "arpack", {}),
    ("pardiso MKL 1 thread", "pardiso", "block", {"MKL_NUM_THREADS": "1"}),
    ("pardiso single", "pardiso-single", "block", {}),
    ("SLEPc + MUMPS", "slepc-mumps", "slepc", {}),
    ("SLEPc + CHOLMOD", "slepc-cholmod", "slepc", {}),
    ("cholmod", "cholmod", "block", {}),
    ("splu (ours: symmetric)", "splu", "block", {}),
    ("splu (scipy default)", "splu-scipy-default", "block", {}),
    ("splu (scipy default) + ARPACK", "splu-scipy-default", "arpack", {}),
]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a small box instead of the link")
    ap.add_argument("--tet10", action="store_true", help="also the Tet10 link (slow with splu)")
    ap.add_argument("--no-splu", action="store_true")
    ap.add_argument("--bar", metavar="NXxNYxNZ",
                    help="the Tet10 bar of reduction.py instead of the link (88x9x9: 191k DOF)")
    ap.add_argument("--repeat", type=int, default=3,
                    help="factorisations and eigen-solves per variant (best kept)")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--backend", help=argparse.SUPPRESS)
    ap.add_argument("--order", type=int, default=1, help=argparse.SUPPRESS)
    ap.add_argument("--method", default="block", help=argparse.SUPPRESS)
    ap.add_argument("--dump", help=argparse.SUPPRESS)
    ap.add_argument("--slepc", help=argparse.SUPPRESS)
    ap.add_argument("--no-slepc", action="store_true", help="skip the SLEPc peers")
    args = ap.parse_args(argv)
    if args.worker:
        worker(args)
        return 0
    if args.slepc:
        slepc_worker(args)
        return 0
    if args.dump:
        dump(args)
        return 0

    from flexarm.fe import available_backends, default_backend

    have = available_backends()
    print(f"date {time.strftime('%Y-%m-%d %H:%M')}, {os.cpu_count()} cores, load average "
          f"{os.getloadavg()[0]:.1f} at start; backends available: {', '.join(have)}; "
          f"default: {default_backend()}")
    if "cholmod" not in have:
        print("cholmod: scikit-sparse not importable, skipped")
    for order in (1, 2) if args.tet10 else (1,):
        rows = []
        for label, backend, method, env in VARIANTS:
            if method == "slepc":
                r = None if args.no_slepc else run_slepc(args, order, backend.split("-")[1])
                if r is not None:
                    rows.append((label, r))
                continue
            if backend.split("-")[0] not in have or (backend.startswith("splu") and args.no_splu):
                continue
            if backend.startswith("splu") and (order == 2 or args.bar) and not args.quick:
                continue  # tens of GB and minutes (DESIGN §10: 218k DOF took 138 s, 10 GB)
            cmd = [sys.executable, __file__, "--worker", "1", "--backend", backend,
                   "--method", method, "--order", str(order), "--repeat", str(args.repeat)] + (
                       ["--quick"] if args.quick else []) + (
                       ["--bar", args.bar] if args.bar else [])
            res = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, **env},
                                 check=False)
            if res.returncode != 0:
                print(f"{label}: failed\n{res.stderr[-2000:]}")
                continue
            rows.append((label, json.loads(res.stdout.strip().splitlines()[-1])))
        if not rows:
            continue
        ref = rows[0][1]
        base = rows[-1][1] if rows[-1][0].endswith("+ ARPACK") and rows[-1][0].startswith(
            "splu (scipy") else None
        print(f"\n{ref['what']}: {ref['n']} free DOF, nnz(K_ff) {ref['nnz']}")
        print(f"best of {args.repeat}; first = first factorisation in a fresh process; "
              "x base = baseline time / this time (last row: SciPy default splu + ARPACK)")
        slepc = dict(rows).get("SLEPc + CHOLMOD")
        print(f"{'variant':30s} {'first s':>7s} {'factor s':>8s} {'x base':>7s} {'1 solve':>7s} "
              f"{'20 block':>8s} {'20 loop':>7s} | {'20 modes s':>10s} {'cpu s':>6s} "
              f"{'solves':>6s} {'solves/k':>8s} {'x base':>7s} {'x slepc':>7s} {'max dfreq':>9s}")
        for label, r in rows:
            dfreq = np.max(np.abs(np.subtract(r["freq_hz"], ref["freq_hz"])) / ref["freq_hz"])
            xf = f"{base['factor'] / r['factor']:6.1f}x" if base and "factor" in r else "      -"
            xe = f"{base['eigen'] / r['eigen']:6.1f}x" if base else "      -"
            xs = f"{slepc['eigen'] / r['eigen']:6.2f}x" if slepc else "      -"
            head = (f"{r['factor_first']:7.2f} {r['factor']:8.2f} {xf} {r['solve1']:7.3f} "
                    f"{r['solve20_block']:8.3f} {r['solve20_loop']:7.3f}" if "factor" in r
                    else f"{'-':>7s} {'-':>8s} {'-':>7s} {'-':>7s} {'-':>8s} {'-':>7s}")
            print(f"{label:30s} {head} | {r['eigen']:10.2f} {r['eigen_cpu']:6.2f} "
                  f"{r['eigen_solves']:6d} {r['eigen_solves'] / 20:8.2f} {xe} {xs} {dfreq:9.1e}")
        print(f"first frequencies [Hz]: {np.round(ref['freq_hz'][:6], 2).tolist()}")
    print(f"load average {os.getloadavg()[0]:.1f} at end (2 shared cores: wall times are noisy)")
    print("targets: default within 1.5x of PARDISO, >= 10x faster than SciPy's default splu "
          "(+ ARPACK for the modes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
