#!/usr/bin/env bash
# Builds the vcan guest's initramfs (busybox-static, this directory's init, the kernel's CAN and 9p
# modules) next to the cached kernel, unless one built from the same inputs is there; prints its path.
#   scripts/vcan-guest/make-initramfs.sh KERNEL_DIR      (KERNEL_DIR as printed by fetch-kernel.sh)
set -euo pipefail

kdir=$1
here=$(cd "$(dirname "$0")" && pwd)
busybox=/bin/busybox
[ -x "$busybox" ] || {
  echo "make-initramfs: $busybox is missing (Debian package busybox-static)" >&2
  exit 1
}

# Named by a hash of everything that goes in, so an edited init or a new busybox builds a new one.
key=$( (cat "$here/init" "$kdir/modules.order" "$kdir/version"; sha256sum "$busybox") | sha256sum | cut -c1-16)
image="$kdir/initramfs-$key.cpio.gz"
[ -f "$image" ] && { echo "$image"; exit 0; }

exec 9>"$kdir/.initramfs.lock"
flock 9
[ -f "$image" ] && { echo "$image"; exit 0; }

work=$(mktemp -d "$kdir/.initramfs.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work"/{bin,dev,proc,sys,modules}
cp "$busybox" "$work/bin/busybox"
ln -s busybox "$work/bin/sh"
cp "$here/init" "$work/init"
chmod 755 "$work/init"
cp "$kdir/modules.order" "$work/modules.order"
cp "$kdir"/modules/*.ko "$work/modules/"
(cd "$work" && find . -mindepth 1 | "$busybox" cpio -o -H newc 2>/dev/null) | gzip -1 >"$image.tmp"
rm -f "$kdir"/initramfs-*.cpio.gz
mv "$image.tmp" "$image"
echo "$image"
