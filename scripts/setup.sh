#!/usr/bin/env bash
# Installs the Debian packages hybridwalk needs (only those missing).
# Run as root on Debian 12. Idempotent. `--test` adds what the test suite
# needs beyond building and running: Xvfb (windowed tests), clang (libFuzzer),
# Chromium (the report's headless-browser check) and Slurm + munge for the
# one-node test cluster (scripts/slurm-cluster.sh; docs/slurm.md). Packages
# are installed under a policy-rc.d that exits 101, so no system service
# (munge, slurmd, slurmctld) is started by the installation.
set -euo pipefail
pkgs=(
  build-essential cmake ninja-build pkg-config git
  libegl-dev libegl-mesa0 libosmesa6-dev libgl-dev mesa-common-dev libglfw3-dev libglm-dev libassimp-dev
  libstb-dev libcli11-dev nlohmann-json3-dev libzip-dev
  libgtest-dev libgmock-dev libbenchmark-dev
)
if [ "${1:-}" = "--test" ]; then
  pkgs+=(ccache xvfb xauth clang libclang-rt-14-dev chromium slurmd slurmctld slurm-client munge)
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#pkgs[@]} packages present"
  exit 0
fi
echo "setup: installing ${#missing[@]} missing packages: ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: need root to install packages (run as root, or install: ${missing[*]})" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
# Block service starts during the install (Debian's invoke-rc.d honours
# /usr/sbin/policy-rc.d; exit 101 = "action forbidden"). An existing policy
# file is kept and restored.
policy=/usr/sbin/policy-rc.d
saved=""
if [ -e "$policy" ]; then saved=$(mktemp); cp -p "$policy" "$saved"; fi
restore_policy() { if [ -n "$saved" ]; then cp -p "$saved" "$policy"; rm -f "$saved"; else rm -f "$policy"; fi; }
trap restore_policy EXIT
printf '#!/bin/sh\nexit 101\n' > "$policy"
chmod 755 "$policy"
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
