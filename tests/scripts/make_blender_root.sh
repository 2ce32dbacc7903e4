#!/bin/bash
# Builds, once per machine, a Debian trixie root that holds a real Blender binary (Debian's
# package: 4.3.2 in trixie, the one Blender binary these machines can install), Xvfb, xdotool
# and ImageMagick, for the tests that run a real `blender` (tests/real_blender); pytest and Node.js
# for the suite's batch tests and the glTF validator run inside it.
#
# Usage: make_blender_root.sh DIR
# Exit 0 with the root ready; exit 3 with one sentence on stderr where this machine cannot
# build it (not root, no debootstrap and no apt-get to install it); any other failure is an error.
# A finished root is left as it is; a half-built one (no stamp) is built on.
set -euo pipefail
root=${1:?usage: make_blender_root.sh DIR}
stamp="$root/.seamless-ao-root"
packages="blender xvfb xdotool x11-utils imagemagick python3-numpy python3-pytest nodejs"
[ -f "$stamp" ] && [ "$(cat "$stamp")" = "$packages" ] && exit 0

if [ "$(id -u)" -ne 0 ]; then
  echo "the real-Blender root needs root (debootstrap and chroot), and this user is not root" >&2; exit 3
fi
if ! command -v debootstrap >/dev/null; then
  if ! command -v apt-get >/dev/null; then
    echo "the real-Blender root needs debootstrap, and this machine has neither it nor apt-get" >&2; exit 3
  fi
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null
fi

echo "== real Blender: building a Debian trixie root in $root (once per machine, a few minutes)"
mkdir -p "$root"
[ -x "$root/usr/bin/apt-get" ] || debootstrap --variant=minbase --include=ca-certificates trixie "$root" >/dev/null
unmount() { umount -l "$root/dev" 2>/dev/null || true; umount -l "$root/proc" 2>/dev/null || true; }
trap unmount EXIT
mountpoint -q "$root/proc" || mount -t proc proc "$root/proc"
mountpoint -q "$root/dev" || mount --bind /dev "$root/dev"
chroot "$root" env DEBIAN_FRONTEND=noninteractive bash -c \
  "apt-get update -qq && apt-get install -y -qq --no-install-recommends $packages >/dev/null"
ln -sf /proc/self/mounts "$root/etc/mtab"     # Blender asks for the mounted file systems
chroot "$root" blender --version 2>/dev/null | head -1
echo "$packages" > "$stamp"
