"""Matrix Market bundles as other tools read them: coordinate form with both triangles,
equal to the superelement through SciPy's ``mmread`` and through Eigen's ``loadMarket``
(a compiled reader, when g++ and Eigen are installed); folder and files follow the
umask."""

import os
import shutil
import stat
import subprocess
from pathlib import Path

import numpy as np
import pytest
import scipy.io
from reduction_helpers import STEEL

from flexarm.reduction import formats
from flexarm.reduction.reduce import reduce_part

_EIGEN_READER = r"""
#include <Eigen/Sparse>
#include <unsupported/Eigen/SparseExtra>
#include <cstdio>
int main(int argc, char** argv) {
  for (int a = 1; a < argc; ++a) {
    Eigen::SparseMatrix<double> A;
    if (!Eigen::loadMarket(A, argv[a])) return 1;
    Eigen::MatrixXd D(A);
    std::printf("%ld %ld\n", (long)D.rows(), (long)D.cols());
    for (Eigen::Index i = 0; i < D.rows(); ++i)
      for (Eigen::Index j = 0; j < D.cols(); ++j) std::printf("%.17g\n", D(i, j));
  }
  return 0;
}
"""


@pytest.fixture(scope="module")
def bundle(bar, tmp_path_factory):
    mesh, regions, KM = bar
    se = reduce_part(mesh, STEEL, regions, "rbe2", "cb", 5, matrices=KM)
    return se, formats.write(tmp_path_factory.mktemp("mtx") / "link.mtx", se)


def test_coordinate_form_read_by_scipy(bundle):
    se, path = bundle
    for name in ("K", "M"):
        head = (path / f"{name}.mtx").read_text().splitlines()[0]
        assert head == "%%MatrixMarket matrix coordinate real general"
        A = scipy.io.mmread(path / f"{name}.mtx")
        assert A.nnz == np.count_nonzero(getattr(se, name))
        assert np.array_equal(A.toarray(), getattr(se, name))


def _eigen_include() -> str | None:
    found = subprocess.run(["pkg-config", "--cflags-only-I", "eigen3"], capture_output=True,
                           text=True) if shutil.which("pkg-config") else None
    dirs = [d[2:] for d in (found.stdout.split() if found and not found.returncode else [])]
    dirs += ["/usr/include/eigen3", "/usr/local/include/eigen3"]
    return next((d for d in dirs if (Path(d) / "unsupported/Eigen/SparseExtra").is_file()), None)


@pytest.mark.skipif(shutil.which("g++") is None or _eigen_include() is None,
                    reason="needs g++ and Eigen (apt-get install libeigen3-dev)")
def test_eigen_load_market_reads_what_scipy_reads(bundle, tmp_path):
    se, path = bundle
    (tmp_path / "read.cpp").write_text(_EIGEN_READER)
    subprocess.run(["g++", "-O0", "-std=c++14", f"-I{_eigen_include()}", "read.cpp", "-o",
                    "read"], cwd=tmp_path, check=True, capture_output=True)
    res = subprocess.run([str(tmp_path / "read"), str(path / "K.mtx"), str(path / "M.mtx")],
                         capture_output=True, text=True, check=True)
    assert not res.stderr  # loadMarket reports a count mismatch or a bad line there
    values = res.stdout.split()
    for name in ("K", "M"):
        n, m = int(values[0]), int(values[1])
        A = np.array([float(v) for v in values[2 : 2 + n * m]]).reshape(n, m)
        values = values[2 + n * m :]
        assert np.array_equal(A, scipy.io.mmread(path / f"{name}.mtx").toarray()), name
        assert np.array_equal(A, getattr(se, name)), name


@pytest.mark.parametrize("umask", [0o022, 0o077])
def test_bundle_follows_the_umask(bundle, tmp_path, umask):
    se, _ = bundle
    old = os.umask(umask)
    try:
        path = formats.write(tmp_path / "link.mtx", se)
    finally:
        os.umask(old)
    assert stat.S_IMODE(path.stat().st_mode) == 0o777 & ~umask
    for f in path.iterdir():
        assert stat.S_IMODE(f.stat().st_mode) == 0o666 & ~umask, f.name
