# ruff: noqa: T201 - a benchmark prints its figures
"""Benchmark: sparse direct backends on one clamped link, factorisation and 20 modes.

For each backend (``pardiso``, ``splu``, ``cholmod`` when scikit-sparse imports) and
thread setting, a subprocess assembles the same K, M (so the threading environment is
set before any BLAS loads), eliminates the clamped DOFs and times:

* the factorisation of K_ff (SPD),
* one solve, 20 right-hand sides in one call, and 20 one-by-one,
* ``modes(K, M, n=20, eigensolver=shift_invert(0.0, backend))``: factorisation plus
  ARPACK (the modes are checked against the first row's).

Thread variants set ``MKL_NUM_THREADS`` (PARDISO) and ``OPENBLAS_NUM_THREADS`` (SciPy's
BLAS, used by ARPACK) for the whole worker.  ``splu (scipy default COLAMD)`` is plain
``scipy.sparse.linalg.splu(K)``, the baseline of the issue's target.

Ratios are to PARDISO with the default threads, measured in the same run.  Not a test.

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

    # shift 0 (clamped part): the eigensolver factorises K itself, as a user's call would
    t = time.perf_counter()
    if args.backend == "splu-scipy-default":
        m = modes(Kf, Mf, n=20, eigensolver=shift_invert(0.0), factor=_factor(Kf, args.backend))
    else:
        m = modes(Kf, Mf, n=20, eigensolver=shift_invert(0.0, backend=args.backend))
    out["eigen"] = time.perf_counter() - t
    out["freq_hz"] = m.freq_hz.tolist()
    print(json.dumps(out))


VARIANTS = [
    # (label, backend, environment)
    ("pardiso", "pardiso", {}),
    ("pardiso MKL 1 thread", "pardiso", {"MKL_NUM_THREADS": "1"}),
    ("pardiso OPENBLAS 1 thread", "pardiso", {"OPENBLAS_NUM_THREADS": "1"}),
    ("pardiso, both 1 thread", "pardiso", {"MKL_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}),
    ("cholmod", "cholmod", {}),
    ("splu (ours: symmetric mode)", "splu", {}),
    ("splu (scipy default COLAMD)", "splu-scipy-default", {}),
]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a small box instead of the link")
    ap.add_argument("--tet10", action="store_true", help="also the Tet10 link (slow with splu)")
    ap.add_argument("--no-splu", action="store_true")
    ap.add_argument("--repeat", type=int, default=3, help="factorisations per variant (best kept)")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--backend", help=argparse.SUPPRESS)
    ap.add_argument("--order", type=int, default=1, help=argparse.SUPPRESS)
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
        for label, backend, env in VARIANTS:
            if backend.split("-")[0] not in have or (backend.startswith("splu") and args.no_splu):
                continue
            if backend.startswith("splu") and order == 2 and not args.quick:
                continue  # tens of GB and minutes (DESIGN §10: 218k DOF took 138 s, 10 GB)
            cmd = [sys.executable, __file__, "--worker", "1", "--backend", backend,
                   "--order", str(order), "--repeat", str(args.repeat)] + (
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
        print(f"\n{ref['what']}: {ref['n']} free DOF, nnz(K_ff) {ref['nnz']}")
        print(f"factor s = best of {args.repeat}; first = first call in a fresh process")
        print(f"{'backend':26s} {'first s':>7s} {'factor s':>8s} {'x PARDISO':>9s} {'1 solve':>8s} "
              f"{'20 block':>8s} {'20 loop':>8s} {'20 modes s':>10s} {'x PARDISO':>9s} "
              f"{'max dfreq':>9s}")
        for label, r in rows:
            dfreq = np.max(np.abs(np.subtract(r["freq_hz"], ref["freq_hz"])) / ref["freq_hz"])
            print(f"{label:26s} {r['factor_first']:7.2f} {r['factor']:8.2f} "
                  f"{r['factor'] / ref['factor']:8.1f}x "
                  f"{r['solve1']:8.3f} {r['solve20_block']:8.3f} {r['solve20_loop']:8.3f} "
                  f"{r['eigen']:10.2f} {r['eigen'] / ref['eigen']:8.1f}x {dfreq:9.1e}")
        print(f"first frequencies [Hz]: {np.round(ref['freq_hz'][:6], 2).tolist()}")
    print(f"load average {os.getloadavg()[0]:.1f} at end (2 shared cores: wall times are noisy)")
    print("targets: default within 1.5x of PARDISO, >= 10x faster than splu (scipy default)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
