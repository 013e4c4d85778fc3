#!/usr/bin/env bash
# Install flexarm on a fresh Debian/Ubuntu machine: system OpenGL libraries for
# off-screen PyVista rendering (EGL + Mesa, with OSMesa as a fallback), then the
# package itself.  Usage: bash install.sh [--test | --mpi]   (--test adds the test extras
# and, like --mpi, the PETSc/SLEPc environment .venv/mpi for `--backend petsc`)
set -euo pipefail
cd "$(dirname "$0")"

GL_PACKAGES="libegl1 libgl1 libgl1-mesa-dri libosmesa6 libxrender1"
LIBS="libEGL.so.1 libOSMesa.so"
if [ "${1:-}" = "--test" ]; then
  # the optional gmsh mesher (tested with --test) loads these X/GL libraries at import
  GL_PACKAGES="$GL_PACKAGES libglu1-mesa libxcursor1 libxft2 libxinerama1 libgomp1"
  LIBS="$LIBS libGLU.so.1 libXcursor.so.1 libXft.so.2 libXinerama.so.1 libgomp.so.1"
fi
need_gl=0
for lib in $LIBS; do
  ldconfig -p 2>/dev/null | grep -q "$lib" || need_gl=1
done
# the compiled assembly (flexarm/fe/_rows.c) needs a C compiler and Python's headers;
# without them the install still succeeds and assembly runs its NumPy path
if ! command -v cc >/dev/null 2>&1; then GL_PACKAGES="$GL_PACKAGES gcc libc6-dev"; need_gl=1; fi
if ! python -c "import os, sys, sysconfig; sys.exit(not os.path.isfile(os.path.join(sysconfig.get_paths()['include'], 'Python.h')))"; then
  GL_PACKAGES="$GL_PACKAGES python3-dev"; need_gl=1
fi
if [ "$need_gl" = 1 ] && command -v apt-get >/dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" != 0 ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
      echo "install.sh: not root and no sudo: install $GL_PACKAGES yourself (pictures, compiled assembly)" >&2
      SUDO="skip"
    fi
  fi
  if [ "$SUDO" != "skip" ]; then
    echo "install.sh: installing system libraries (off-screen rendering, compiled assembly): $GL_PACKAGES"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $GL_PACKAGES >/dev/null
  fi
fi

extras=""
if [ "${1:-}" = "--test" ]; then extras="[test]"; fi
python -m pip install --disable-pip-version-check -q -e ".${extras}"
# An editable install is never byte-compiled, and PYTHONDONTWRITEBYTECODE may forbid it at
# run time: compile once here so every flexarm command starts faster.
python -m compileall -q flexarm >/dev/null || true
echo "install.sh: flexarm installed ($(python -c 'import flexarm; print(flexarm.__version__)'))"

# The MPI extra (--test or --mpi): `mpiexec -n N .venv/mpi/bin/flexarm reduce ... --backend
# petsc`.  PyPI has petsc4py/slepc4py only as sources whose build downloads PETSc and its
# solvers; Debian ships them built (3.18, with MUMPS) for its own /usr/bin/python3.  So we
# install those packages and a venv on that interpreter that sees them
# (--system-site-packages), with flexarm editable in it.  numpy stays 1.x there, the ABI
# petsc4py was built for.  Failure here only costs the MPI backend (its tests then skip).
if [ "${1:-}" = "--test" ] || [ "${1:-}" = "--mpi" ]; then
  MPI_PACKAGES="python3-petsc4py python3-slepc4py python3-mpi4py openmpi-bin python3-venv"
  if command -v apt-get >/dev/null 2>&1 && ! dpkg -s $MPI_PACKAGES >/dev/null 2>&1; then
    SUDO=""; [ "$(id -u)" != 0 ] && command -v sudo >/dev/null 2>&1 && SUDO="sudo"
    echo "install.sh: installing PETSc/SLEPc/MPI for the petsc backend: $MPI_PACKAGES"
    { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq \
        --no-install-recommends $MPI_PACKAGES >/dev/null; } \
      || echo "install.sh: could not install $MPI_PACKAGES: no petsc backend" >&2
  fi
  mpi_venv() {  # run in an `||` context: any failing step returns instead of exiting
    local petsc_dir slepc_dir site venv=.venv/mpi
    petsc_dir=$(ls -d /usr/lib/petscdir/petsc3.*/*-real 2>/dev/null | sort -V | tail -1)
    slepc_dir=$(ls -d /usr/lib/slepcdir/slepc3.*/*-real 2>/dev/null | sort -V | tail -1)
    [ -n "$petsc_dir" ] && [ -n "$slepc_dir" ] && [ -x /usr/bin/python3 ] || return 1
    [ -x "$venv/bin/python" ] || /usr/bin/python3 -m venv --system-site-packages "$venv" \
      || return 1
    site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])') \
      || return 1
    # Debian's .pth files look for /usr/lib/petsc, which only the -dev packages create.
    printf '%s\n' "$petsc_dir/lib/python3/dist-packages" "$slepc_dir/lib/python3/dist-packages" \
      > "$site/flexarm_petsc.pth" || return 1
    echo 'numpy<2' > "$venv/constraints.txt" || return 1
    PIP_CONSTRAINT="$venv/constraints.txt" "$venv/bin/python" -m pip install \
      --disable-pip-version-check -q -e ".[mpi]" || return 1
    echo "install.sh: petsc backend ready: mpiexec -n N $venv/bin/flexarm reduce ... --backend petsc"
  }
  mpi_venv || echo "install.sh: no MPI environment (.venv/mpi): no petsc backend" >&2
fi

# The Matrix Market test compiles a reader against Eigen's loadMarket (a failure only
# skips that test).
if [ "${1:-}" = "--test" ] && command -v apt-get >/dev/null 2>&1 \
    && { ! command -v g++ >/dev/null 2>&1 \
         || [ ! -f /usr/include/eigen3/unsupported/Eigen/SparseExtra ]; }; then
  SUDO=""; [ "$(id -u)" != 0 ] && command -v sudo >/dev/null 2>&1 && SUDO="sudo"
  echo "install.sh: installing g++ and libeigen3-dev for the Matrix Market test"
  { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq \
      --no-install-recommends g++ libeigen3-dev >/dev/null; } \
    || echo "install.sh: could not install g++ and Eigen: the loadMarket check skips" >&2
fi

# The docs test opens the built site in a headless browser: Debian's chromium and its
# driver (a failure only skips that test).
if [ "${1:-}" = "--test" ] && ! command -v chromedriver >/dev/null 2>&1 \
    && command -v apt-get >/dev/null 2>&1; then
  SUDO=""; [ "$(id -u)" != 0 ] && command -v sudo >/dev/null 2>&1 && SUDO="sudo"
  echo "install.sh: installing chromium and chromium-driver for the docs test"
  { $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq \
      --no-install-recommends chromium chromium-driver >/dev/null; } \
    || echo "install.sh: could not install chromium: the browser check of the docs skips" >&2
fi
