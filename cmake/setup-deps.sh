#!/usr/bin/env bash
# Installs what Epaphe needs on Debian bookworm and builds Trilinos 13.2 from Debian's source
# package with Kokkos OpenMP and Amesos2 over MUMPS, into a prefix outside the work tree.
#
#   EPAPHE_DEPS_PREFIX  where dependencies go        (default /opt/epaphe-deps)
#   EPAPHE_JOBS         parallel build jobs          (default: number of cores)
#
# The build is skipped when a Trilinos with the same configuration is already installed there
# (a hash of the configure options is stored beside it). Progress is printed as it goes; the full
# logs are kept in $EPAPHE_DEPS_PREFIX/logs.
set -euo pipefail

PREFIX="${EPAPHE_DEPS_PREFIX:-/opt/epaphe-deps}"
JOBS="${EPAPHE_JOBS:-$(nproc)}"
TRILINOS_VERSION=13.2.0
TRILINOS_PREFIX="$PREFIX/trilinos-$TRILINOS_VERSION"
LOGS="$PREFIX/logs"

say() { printf '[setup] %s\n' "$*"; }
die() { printf '[setup] error: %s\n' "$*" >&2; exit 1; }

# ---------------------------------------------------------------------------------------------
# 1. Debian packages
# ---------------------------------------------------------------------------------------------
DEB_PACKAGES=(
  build-essential cmake gfortran pkg-config ccache dpkg-dev
  libopenmpi-dev openmpi-bin
  libmumps-dev libscalapack-openmpi-dev
  libopenblas-dev liblapack-dev
  libhdf5-openmpi-dev hdf5-tools
  libgtest-dev
  python3 python3-numpy python3-h5py python3-matplotlib python3-venv python3-pip python3-setuptools python3-mypy
  clang-format black doxygen
  calculix-ccx
  python3-siconos
)

missing=()
for p in "${DEB_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  [ "$(id -u)" = 0 ] || die "packages missing (${missing[*]}) and not root: install them with apt-get as root, then run again."
  say "installing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  say "Debian packages: all present"
fi

# ---------------------------------------------------------------------------------------------
# 2. Trilinos from Debian's source package
# ---------------------------------------------------------------------------------------------
# Only the packages Epaphe uses. Explicit instantiation off (20 min instead of over an hour on
# 2 cores); Kokkos OpenMP only; Amesos2 with MUMPS (distributed-correct) and KLU2 (serial only).
TRILINOS_OPTIONS=(
  -DCMAKE_BUILD_TYPE=Release
  -DCMAKE_C_COMPILER=mpicc
  -DCMAKE_CXX_COMPILER=mpicxx
  -DCMAKE_CXX_STANDARD=17
  -DCMAKE_CXX_FLAGS=-w
  -DCMAKE_C_FLAGS=-w
  -DBUILD_SHARED_LIBS=ON
  -DTrilinos_ENABLE_Fortran=OFF
  -DTrilinos_ENABLE_ALL_PACKAGES=OFF
  -DTrilinos_ENABLE_ALL_OPTIONAL_PACKAGES=OFF
  -DTrilinos_ENABLE_SECONDARY_TESTED_CODE=OFF
  -DTrilinos_ENABLE_TESTS=OFF
  -DTrilinos_ENABLE_EXAMPLES=OFF
  -DTrilinos_ENABLE_EXPLICIT_INSTANTIATION=OFF
  -DTrilinos_ENABLE_Teuchos=ON
  -DTrilinos_ENABLE_Kokkos=ON
  -DTrilinos_ENABLE_KokkosKernels=ON
  -DTrilinos_ENABLE_Tpetra=ON
  -DTrilinos_ENABLE_Belos=ON
  -DTrilinos_ENABLE_Anasazi=ON
  -DTrilinos_ENABLE_Amesos2=ON
  -DTrilinos_ENABLE_Epetra=OFF
  -DTrilinos_ENABLE_OpenMP=ON
  -DKokkos_ENABLE_OPENMP=ON
  -DKokkos_ENABLE_SERIAL=OFF
  -DKokkos_ENABLE_THREADS=OFF
  -DKokkos_ENABLE_PTHREAD=OFF
  -DTpetra_INST_OPENMP=ON
  -DTpetra_INST_SERIAL=OFF
  -DTpetra_INST_INT_INT=ON
  -DTpetra_INST_DOUBLE=ON
  -DTPL_ENABLE_MPI=ON
  -DTPL_ENABLE_Pthread=OFF
  -DTPL_ENABLE_BLAS=ON
  -DTPL_ENABLE_LAPACK=ON
  -DTPL_ENABLE_MUMPS=ON
  "-DMUMPS_LIBRARY_NAMES=dmumps;mumps_common;pord"
  -DMUMPS_INCLUDE_DIRS=/usr/include
  -DTPL_ENABLE_SCALAPACK=ON
  -DSCALAPACK_LIBRARY_NAMES=scalapack-openmpi
  -DAmesos2_ENABLE_MUMPS=ON
  -DAmesos2_ENABLE_KLU2=ON
  -DTPL_ENABLE_HDF5=OFF
  -DTPL_ENABLE_Boost=OFF
  -DTPL_ENABLE_DLlib=OFF
)

config_hash=$(printf '%s\n' "$TRILINOS_VERSION" "${TRILINOS_OPTIONS[@]}" | sha256sum | cut -c1-16)
stamp="$TRILINOS_PREFIX/.epaphe-config"

if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$config_hash" ] \
   && [ -f "$TRILINOS_PREFIX/lib/cmake/Trilinos/TrilinosConfig.cmake" ]; then
  say "Trilinos $TRILINOS_VERSION (OpenMP, MUMPS) already installed in $TRILINOS_PREFIX (config $config_hash)"
  exit 0
fi

mkdir -p "$PREFIX/src" "$LOGS"
src="$PREFIX/src/trilinos-$TRILINOS_VERSION"
if [ ! -f "$src/CMakeLists.txt" ]; then
  [ "$(id -u)" = 0 ] || die "Trilinos source missing in $src and not root: cannot enable deb-src."
  # Debian's source packages need deb-src lines; enable them if the machine has none.
  if ! grep -rqsE '^(Types:.*deb-src|deb-src )' /etc/apt/sources.list /etc/apt/sources.list.d/; then
    say "enabling deb-src in /etc/apt/sources.list.d/debian.sources"
    sed -i 's/^Types: deb$/Types: deb deb-src/' /etc/apt/sources.list.d/debian.sources
  fi
  apt-get update -qq
  say "fetching Debian's source package of Trilinos $TRILINOS_VERSION (166 MB)"
  (cd "$PREFIX/src" && apt-get source -qq "trilinos=${TRILINOS_VERSION}-4" >"$LOGS/trilinos-source.log" 2>&1) \
    || (cd "$PREFIX/src" && apt-get source -qq trilinos >"$LOGS/trilinos-source.log" 2>&1) \
    || die "apt-get source trilinos failed; see $LOGS/trilinos-source.log"
  [ -f "$src/CMakeLists.txt" ] || die "expected $src after apt-get source; see $LOGS/trilinos-source.log"
fi

build="$PREFIX/build/trilinos-$TRILINOS_VERSION"
rm -rf "$build"; mkdir -p "$build"
start=$(date +%s)
say "configuring Trilinos (log: $LOGS/trilinos-configure.log)"
(cd "$build" && cmake "$src" -DCMAKE_INSTALL_PREFIX="$TRILINOS_PREFIX" \
   -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache \
   "${TRILINOS_OPTIONS[@]}" >"$LOGS/trilinos-configure.log" 2>&1) \
  || { tail -30 "$LOGS/trilinos-configure.log"; die "Trilinos configure failed; see $LOGS/trilinos-configure.log"; }

say "building Trilinos with $JOBS jobs (about 20 min on 2 cores; log: $LOGS/trilinos-build.log)"
# Print a line each time the overall percentage moves, with the elapsed time (a shell loop:
# mawk would buffer its input and print nothing until the end).
set +e
(cd "$build" && make -j"$JOBS" 2>&1) | tee "$LOGS/trilinos-build.log" | {
  last=""
  while IFS= read -r line; do
    if [[ "$line" =~ ^\[\ *([0-9]+)%\] ]] && [ "${BASH_REMATCH[1]}" != "$last" ]; then
      last="${BASH_REMATCH[1]}"; now=$(date +%s)
      printf '[setup] Trilinos build %3s %%  (%d min %02d s)\n' "$last" $(( (now-start)/60 )) $(( (now-start)%60 ))
    fi
  done
}
rc=${PIPESTATUS[0]}
set -e
[ "$rc" = 0 ] || { grep -m5 -B2 -A10 'error' "$LOGS/trilinos-build.log" | tail -40; die "Trilinos build failed; see $LOGS/trilinos-build.log"; }

say "installing Trilinos into $TRILINOS_PREFIX"
(cd "$build" && make install >"$LOGS/trilinos-install.log" 2>&1) || die "Trilinos install failed; see $LOGS/trilinos-install.log"
echo "$config_hash" > "$stamp"
end=$(date +%s)
say "Trilinos ready in $(( (end-start)/60 )) min $(( (end-start)%60 )) s"
echo "$((end-start))" > "$TRILINOS_PREFIX/.epaphe-build-seconds"
rm -rf "$build"
