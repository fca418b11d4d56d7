#!/usr/bin/env bash
# Installs the Debian packages budget-slam needs, only those that are missing. Idempotent.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libmrpt-dev mrpt-apps            # MRPT 2.5: libraries, kf-slam, rawlog-edit, simul-landmarks
  libeigen3-dev libsuitesparse-dev # linear algebra, CHOLMOD
  libtclap-dev nlohmann-json3-dev  # command line, JSON output
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-matplotlib  # experiment scripts and plots
  python3-scipy                    # experiment statistics (Wilcoxon signed-rank test)
  clang-format
  slurm-wlm munge                  # sweeps on a SLURM cluster; tools/slurm/local-cluster.sh
  python3-dev pybind11-dev         # the budget_slam Python module
  clang-14 libclang-rt-14-dev      # libFuzzer targets and sanitizer runtimes (tools/fuzz.sh)
  libglpk-dev                      # offline coverage optimum (integer program)
  libcairo2-dev fonts-dejavu-core  # figures as PNG, PDF and SVG
  poppler-utils                    # the figures test renders each PDF (pdftoppm, pdftotext)
)

# The figures are drawn in DejaVu Sans: a font cache older than the font (packages installed
# without their triggers having run) makes cairo fall back to another face, whose PDF text then
# extracts with letters missing. Rebuild the cache when the face is not found.
font_cache() {
  if command -v fc-match >/dev/null 2>&1 &&
     ! fc-match -f '%{family}' 'DejaVu Sans' 2>/dev/null | grep -q 'DejaVu Sans'; then
    fc-cache -f >/dev/null 2>&1 || true
  fi
}

# One dpkg-query for every package (not one a package: this runs before every demo and test).
installed="$(dpkg-query -W -f='${Package} ${Status}\n' "${PACKAGES[@]}" 2>/dev/null |
             awk '$4 == "installed" {print $1}' || true)"
missing=()
for p in "${PACKAGES[@]}"; do
  if ! grep -qx -- "$p" <<< "$installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  font_cache
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"

font_cache
