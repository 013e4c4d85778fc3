#!/usr/bin/env bash
# Install flexarm on a fresh Debian/Ubuntu machine: system OpenGL libraries for
# off-screen PyVista rendering (EGL + Mesa, with OSMesa as a fallback), then the
# package itself.  Usage: bash install.sh [--test]   (--test adds the test extras)
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
if [ "$need_gl" = 1 ] && command -v apt-get >/dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" != 0 ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
      echo "install.sh: not root and no sudo: install $GL_PACKAGES yourself for pictures" >&2
      SUDO="skip"
    fi
  fi
  if [ "$SUDO" != "skip" ]; then
    echo "install.sh: installing OpenGL libraries for off-screen rendering: $GL_PACKAGES"
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
