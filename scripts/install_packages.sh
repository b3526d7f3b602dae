#!/bin/bash
# install_packages.sh PACKAGE... : installs, with apt-get, the Debian packages
# of the list that are not installed yet (sudo when not root). The one place
# the project's scripts install packages. Exit 0 when all are there.
set -euo pipefail
missing=()
for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -gt 0 ] || exit 0
echo "install_packages: installing ${missing[*]}" >&2
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
apt=(apt-get -o DPkg::Lock::Timeout=300)
$SUDO "${apt[@]}" update -qq
DEBIAN_FRONTEND=noninteractive $SUDO "${apt[@]}" install -y -qq --no-install-recommends "${missing[@]}" >&2
