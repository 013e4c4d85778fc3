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

    python benchmarks/solvers.py            # clamped Tet4 link, ~66k DOF
    python benchmarks/solvers.py --tet10    # also the Tet10 version of the same link
    python benchmarks/solvers.py --quick    # small box, seconds
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

#: fTetWild edge of the solver link [m]: 76k Tet4, 68k DOF (66k free), like DESIGN §10.
SOLVER_LINK_SIZE = 0.011
#: Clamp the nodes within this fraction of the part's length from its low end.
CLAMP_FRACTION = 0.02


def problem(quick: bool, order: int):
    """(K_ff, M_ff, description) of the clamped link (or a clamped box when ``quick``)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from assembly import link_mesh, perturbed_box

    from flexarm.fe import MATERIALS, assemble, dof_split, node_dofs

    found = None if quick else link_mesh(allow_meshing=True, size=SOLVER_LINK_SIZE)
    mesh, what = found if found else perturbed_box(6_000 if quick else 100_000)
    if order == 2:
        mesh = mesh.to_tet10()
    lo, hi = mesh.bounds()
    axis = int(np.argmax(hi - lo))
    fixed = np.flatnonzero(mesh.points[:, axis] <= lo[axis] + CLAMP_FRACTION * (hi - lo)[axis])
    K, M = assemble(mesh, MATERIALS["steel"])
    split = dof_split(mesh.n_dofs, node_dofs(fixed))
    what = f"{what}, Tet{4 if order == 1 else 10}, {mesh.n_tets} tets, {len(fixed)} clamped nodes"
    return split.condense(K), split.condense(M), what


def _factor(K, backend: str):
    """Our factorisation, or plain ``scipy.sparse.linalg.splu(K)`` (COLAMD, partial
    pivoting: what a user gets without options) for ``splu-scipy-default``."""
    from flexarm.fe import Factor, factorize

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

    Kf, Mf, what = problem(args.quick, args.order)
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
    solver = shift_invert(0.0, backend=None if baseline else args.backend, method=args.method)
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


VARIANTS = [
    # (label, backend, eigen method, environment); the last one is the baseline
    ("pardiso", "pardiso", "block", {}),
    ("pardiso + ARPACK", "pardiso", "arpack", {}),
    ("pardiso MKL 1 thread", "pardiso", "block", {"MKL_NUM_THREADS": "1"}),
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
    ap.add_argument("--repeat", type=int, default=3,
                    help="factorisations and eigen-solves per variant (best kept)")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--backend", help=argparse.SUPPRESS)
    ap.add_argument("--order", type=int, default=1, help=argparse.SUPPRESS)
    ap.add_argument("--method", default="block", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        worker(args)
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
            if backend.split("-")[0] not in have or (backend.startswith("splu") and args.no_splu):
                continue
            if backend.startswith("splu") and order == 2 and not args.quick:
                continue  # tens of GB and minutes (DESIGN §10: 218k DOF took 138 s, 10 GB)
            cmd = [sys.executable, __file__, "--worker", "1", "--backend", backend,
                   "--method", method, "--order", str(order), "--repeat", str(args.repeat)] + (
                       ["--quick"] if args.quick else [])
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
        print(f"{'variant':30s} {'first s':>7s} {'factor s':>8s} {'x base':>7s} {'1 solve':>7s} "
              f"{'20 block':>8s} {'20 loop':>7s} | {'20 modes s':>10s} {'cpu s':>6s} "
              f"{'solves':>6s} {'x base':>7s} {'max dfreq':>9s}")
        for label, r in rows:
            dfreq = np.max(np.abs(np.subtract(r["freq_hz"], ref["freq_hz"])) / ref["freq_hz"])
            xf = f"{base['factor'] / r['factor']:6.1f}x" if base else "      -"
            xe = f"{base['eigen'] / r['eigen']:6.1f}x" if base else "      -"
            print(f"{label:30s} {r['factor_first']:7.2f} {r['factor']:8.2f} {xf} "
                  f"{r['solve1']:7.3f} {r['solve20_block']:8.3f} {r['solve20_loop']:7.3f} | "
                  f"{r['eigen']:10.2f} {r['eigen_cpu']:6.2f} {r['eigen_solves']:6d} {xe} "
                  f"{dfreq:9.1e}")
        print(f"first frequencies [Hz]: {np.round(ref['freq_hz'][:6], 2).tolist()}")
    print(f"load average {os.getloadavg()[0]:.1f} at end (2 shared cores: wall times are noisy)")
    print("targets: default within 1.5x of PARDISO, >= 10x faster than SciPy's default splu "
          "(+ ARPACK for the modes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
