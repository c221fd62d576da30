#!/usr/bin/env bash
# Installs every Debian package listed in scripts/packages.txt (one per line, '#' starts a comment).
#
#   bash scripts/install-packages.sh
#
# Idempotent and non-interactive: when dpkg already reports every package installed it touches nothing (no
# apt-get update, no network); otherwise it runs `apt-get update` once and installs only what is missing,
# without recommended packages. Runs as root, or through sudo when not root and sudo exists.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
list="${1:-$here/packages.txt}"

if [[ ! -r "$list" ]]; then
  echo "install-packages: cannot read package list $list" >&2
  exit 1
fi

# Package names: strip comments and blanks.
mapfile -t packages < <(sed -e 's/#.*//' -e 's/[[:space:]]\+/\n/g' "$list" | sed '/^$/d')
if ((${#packages[@]} == 0)); then
  echo "install-packages: $list lists no packages" >&2
  exit 1
fi

# Names that an installed package provides count as installed (NodeSource's nodejs provides npm, and conflicts
# with Debian's npm package: installing that would replace the node a machine already has).
mapfile -t provided < <(dpkg-query -W -f='${Status}\t${Provides}\n' 2>/dev/null |
  sed -n 's/^install ok installed\t//p' | tr ',' '\n' | sed -e 's/(.*)//' -e 's/[[:space:]]//g' | sed '/^$/d' | sort -u)
installed() {
  local status
  status="$(dpkg-query -W -f='${Status}' "$1" 2>/dev/null || true)"
  [[ "$status" == "install ok installed" ]] && return 0
  local name
  for name in "${provided[@]}"; do
    [[ "$name" == "$1" ]] && return 0
  done
  return 1
}

missing=()
for package in "${packages[@]}"; do
  if ! installed "$package"; then
    missing+=("$package")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-packages: all ${#packages[@]} packages from $(basename "$list") are installed"
  exit 0
fi

as_root=()
if [[ "$(id -u)" != 0 ]]; then
  if command -v sudo >/dev/null 2>&1; then
    as_root=(sudo -n)
    # Let an interactive user type a password; in CI (no terminal) fail instead of hanging.
    if [[ -t 0 ]]; then as_root=(sudo); fi
  else
    echo "install-packages: missing packages (${missing[*]}) and not root, no sudo: install them as root" >&2
    exit 1
  fi
fi

echo "install-packages: installing ${#missing[@]} missing package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt_options=(-y -q -o Dpkg::Options::=--force-confdef -o Dpkg::Options::=--force-confold)
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive \
  apt-get install "${apt_options[@]}" --no-install-recommends "${missing[@]}"

# Check that the install did what we asked (a package name typo should fail here, not later in the build).
mapfile -t provided < <(dpkg-query -W -f='${Status}\t${Provides}\n' 2>/dev/null |
  sed -n 's/^install ok installed\t//p' | tr ',' '\n' | sed -e 's/(.*)//' -e 's/[[:space:]]//g' | sed '/^$/d' | sort -u)
still_missing=()
for package in "${missing[@]}"; do
  installed "$package" || still_missing+=("$package")
done
if ((${#still_missing[@]} > 0)); then
  echo "install-packages: still not installed after apt-get: ${still_missing[*]}" >&2
  exit 1
fi
echo "install-packages: done"
