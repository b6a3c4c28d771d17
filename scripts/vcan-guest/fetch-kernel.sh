#!/usr/bin/env bash
# Unpacks Debian's own kernel (the package linux-image-amd64 points to) and the modules the vcan guest
# needs into the cache, without installing it; prints the directory. This machine's kernel has no
# SocketCAN, Debian's has it as modules (can-dev, can, can-raw, vcan).
#   scripts/vcan-guest/fetch-kernel.sh          -> ${SEAR_VCAN_CACHE:-~/.cache/sear/vcan-guest}/linux-image-X
# Kept there until linux-image-amd64 names another version. Offline, the newest cached kernel is used.
set -euo pipefail

cache_root=${SEAR_VCAN_CACHE:-$HOME/.cache/sear/vcan-guest}
mkdir -p "$cache_root"

# The modules asked for (sch_plug: a qdisc that holds frames back, so that the tests can fill an
# interface's transmit queue as a busy real bus does); their dependencies are found from each
# module's own .modinfo (no depmod output ships in the package, and kmod may be missing on the host).
wanted=(virtio_pci 9pnet_virtio 9p vcan can-raw sch_plug)
# A cached kernel counts only if it was unpacked for this same list.
is_ready() { [ -f "$1/ready" ] && [ "$(cat "$1/wanted" 2>/dev/null)" = "${wanted[*]}" ]; }

pkg=$(apt-cache depends linux-image-amd64 2>/dev/null | awk '/Depends: linux-image-[0-9]/ {print $2; exit}' || true)
if [ -z "$pkg" ]; then
  dir=$(ls -d "$cache_root"/linux-image-*/ 2>/dev/null | sort -V | tail -n 1 || true)
  if [ -n "$dir" ] && is_ready "$dir"; then
    echo "${dir%/}"
    exit 0
  fi
  echo "fetch-kernel: apt-cache knows no linux-image-amd64 and no kernel is cached in $cache_root" >&2
  exit 1
fi

dir="$cache_root/$pkg"
is_ready "$dir" && { echo "$dir"; exit 0; }

# Two tests may start at once: one fetches, the other waits for it.
exec 9>"$cache_root/.lock"
flock 9
is_ready "$dir" && { echo "$dir"; exit 0; }

for tool in apt-get dpkg-deb objcopy; do
  command -v "$tool" >/dev/null || { echo "fetch-kernel: $tool is missing" >&2; exit 1; }
done

work=$(mktemp -d "$cache_root/.fetch.XXXXXX")
trap 'rm -rf "$work"' EXIT
# apt-get download runs as _apt when it can; a directory _apt may not write to only makes it warn.
(cd "$work" && apt-get download -q "$pkg" >"$work/apt.log" 2>&1) || {
  cat "$work/apt.log" >&2
  echo "fetch-kernel: could not download $pkg" >&2
  exit 1
}
dpkg-deb -x "$work"/"$pkg"_*.deb "$work/root"
kver=${pkg#linux-image-}
moddir="$work/root/lib/modules/$kver"
[ -d "$moddir" ] || { echo "fetch-kernel: $pkg has no lib/modules/$kver" >&2; exit 1; }

rm -rf "$dir.new"
mkdir -p "$dir.new/modules"
cp "$work/root/boot/vmlinuz-$kver" "$dir.new/vmlinuz"

# Finds a module's file by name (module names treat - and _ alike), decompressed into the cache,
# since busybox insmod loads plain .ko files only.
module_file() {
  local pattern=${1//[-_]/[-_]}
  find "$moddir" -regextype posix-extended -regex ".*/${pattern}\.ko(\.xz|\.zst|\.gz)?" | head -n 1
}
declare -A loaded=()
order=()
add_module() {
  local name=${1//-/_}
  [ -n "${loaded[$name]:-}" ] && return 0
  loaded[$name]=1
  local file
  file=$(module_file "$name")
  if [ -z "$file" ]; then
    # Built into this kernel: nothing to load.
    grep -Eq "/${name//_/[-_]}\.ko\$" "$moddir/modules.builtin" && return 0
    echo "fetch-kernel: $pkg has no module $name" >&2
    exit 1
  fi
  local out="$dir.new/modules/$name.ko"
  case "$file" in
    *.xz) xz -dc "$file" >"$out" ;;
    *.zst) zstd -qdc "$file" >"$out" ;;
    *.gz) gzip -dc "$file" >"$out" ;;
    *) cp "$file" "$out" ;;
  esac
  local deps
  deps=$(objcopy -O binary --only-section=.modinfo "$out" /dev/stdout | tr '\0' '\n' | sed -n 's/^depends=//p')
  local dep
  for dep in ${deps//,/ }; do add_module "$dep"; done
  order+=("$name")
}
for m in "${wanted[@]}"; do add_module "$m"; done
printf '%s\n' "${order[@]}" >"$dir.new/modules.order"
echo "$pkg" >"$dir.new/version"
echo "${wanted[*]}" >"$dir.new/wanted"
touch "$dir.new/ready"
rm -rf "$dir"
mv "$dir.new" "$dir"
# Older kernels are of no further use.
for old in "$cache_root"/linux-image-*; do
  [ "$old" = "$dir" ] || rm -rf "$old"
done
echo "$dir"
