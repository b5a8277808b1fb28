#!/usr/bin/env bash
# apt-get inside a debootstrapped chroot (needs root): `update` once, then the given arguments,
# non-interactive, without apt's sandbox user and accepting a Release file past its Valid-Until
# date (the mirror's Debian unstable). /proc is mounted for the call in a private namespace.
#   scripts/chroot-apt.sh DIR install -y PKG...     scripts/chroot-apt.sh DIR download PKG...
set -euo pipefail
dir=$1; shift
cp -L /etc/resolv.conf "$dir/etc/resolv.conf"
opts="-o Acquire::Check-Valid-Until=false -o APT::Sandbox::User=root -qq"
args=$(printf " %q" "$@")
unshare -m --propagation private sh -c "mount -t proc proc '$dir/proc' && chroot '$dir' sh -c '
  export DEBIAN_FRONTEND=noninteractive
  [ -f /var/lib/apt/.bdi-updated ] || { apt-get $opts update && touch /var/lib/apt/.bdi-updated; }
  cd /tmp && apt-get $opts -y --no-install-recommends $args'; rc=\$?; umount '$dir/proc'; exit \$rc"
