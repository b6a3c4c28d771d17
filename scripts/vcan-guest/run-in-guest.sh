#!/usr/bin/env bash
# Runs one command as root in a qemu guest booted with Debian's kernel, where SocketCAN works and
# vcan0 is up: for hosts whose own kernel has no AF_CAN. The guest sees the host's root read-only,
# a fresh tmpfs on /tmp, /run and /dev/shm, and DIR (if given) writable at its own path.
#   scripts/vcan-guest/run-in-guest.sh [--out DIR] [--timeout SECONDS] -- COMMAND [ARG...]
# COMMAND runs with bash in the caller's directory, which must be visible in the guest (not under
# /tmp unless inside DIR), with PATH, CI and SEAR_* passed on and HOME=/tmp/home. Its stdout and
# stderr come out as this script's, once the guest is off; the guest's console only when the guest
# failed. Exit status: COMMAND's, or 125 when the guest itself failed or timed out (default 300 s,
# or $SEAR_VCAN_TIMEOUT). The kernel and initramfs are cached, see fetch-kernel.sh.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
out_dir=""
limit=${SEAR_VCAN_TIMEOUT:-300}
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out_dir=$(cd "$2" && pwd -P); shift 2 ;;
    --timeout) limit=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "run-in-guest: unknown option $1 (usage: run-in-guest.sh [--out DIR] [--timeout S] -- COMMAND...)" >&2; exit 125 ;;
  esac
done
[ $# -gt 0 ] || { echo "run-in-guest: no command given" >&2; exit 125; }

qemu=$(command -v qemu-system-x86_64 || true)
[ -n "$qemu" ] || { echo "run-in-guest: qemu-system-x86_64 is missing (Debian package qemu-system-x86)" >&2; exit 125; }
kdir=$("$here/fetch-kernel.sh") || { echo "run-in-guest: no guest kernel (see above)" >&2; exit 125; }
initrd=$("$here/make-initramfs.sh" "$kdir") || { echo "run-in-guest: no initramfs (see above)" >&2; exit 125; }

ctl=$(mktemp -d "${TMPDIR:-/tmp}/sear-vcan-guest.XXXXXX")
trap 'rm -rf "$ctl"' EXIT

# Single quotes for busybox sh, which knows no $'...'.
sh_quote() { printf "'%s'" "$(printf '%s' "$1" | sed "s/'/'\\\\''/g")"; }
{
  echo "out_dir=$(sh_quote "$out_dir")"
  echo "caller_dir=$(sh_quote "$PWD")"
} >"$ctl/params"
{
  echo "export PATH=$(sh_quote "$PATH:/usr/sbin:/sbin") HOME=/tmp/home LANG=C.UTF-8"
  for name in CI $(compgen -e | grep '^SEAR_' || true); do
    [ -n "${!name+set}" ] && echo "export $name=$(sh_quote "${!name}")"
  done
  echo 'mkdir -p "$HOME"'
  echo "cd -- $(sh_quote "$PWD") || { echo \"run-in-guest: the caller's directory is not visible in the guest\" >&2; exit 125; }"
  printf 'exec'
  for arg in "$@"; do printf ' %s' "$(sh_quote "$arg")"; done
  echo
} >"$ctl/command.sh"

# TCG by default: on these machines /dev/kvm exists but a KVM guest never boots (nested), and TCG
# boots this guest in seconds. SEAR_VCAN_ACCEL=kvm where KVM works.
accel=${SEAR_VCAN_ACCEL:-tcg}
args=(
  -nodefaults -no-user-config -display none -no-reboot
  -machine "pc,accel=$accel" -m 512M -smp 1
  -kernel "$kdir/vmlinuz" -initrd "$initrd"
  -append "console=ttyS0 quiet loglevel=3 panic=-1 rdinit=/init"
  -serial "file:$ctl/console.log"
  -virtfs "local,path=/,mount_tag=host,security_model=none,readonly=on"
  -virtfs "local,path=$ctl,mount_tag=ctl,security_model=none"
)
[ -n "$out_dir" ] && args+=(-virtfs "local,path=$out_dir,mount_tag=out,security_model=none")

qemu_status=0
timeout -k 5 "$limit" "$qemu" "${args[@]}" >"$ctl/qemu.log" 2>&1 </dev/null || qemu_status=$?

[ -f "$ctl/stdout" ] && cat "$ctl/stdout"
[ -f "$ctl/stderr" ] && cat "$ctl/stderr" >&2
if [ -f "$ctl/status" ] && [ ! -f "$ctl/guest-error" ]; then
  exit "$(cat "$ctl/status")"
fi
{
  if [ "$qemu_status" = 124 ] || [ "$qemu_status" = 137 ]; then
    echo "run-in-guest: the guest did not finish within $limit s"
  elif [ -f "$ctl/guest-error" ]; then
    echo "run-in-guest: guest setup failed: $(cat "$ctl/guest-error")"
  else
    echo "run-in-guest: the guest stopped without the command's status (qemu exit $qemu_status)"
  fi
  echo "--- qemu:"; cat "$ctl/qemu.log" 2>/dev/null
  echo "--- guest console:"; cat "$ctl/console.log" 2>/dev/null
} >&2
exit 125
