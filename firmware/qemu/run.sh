#!/bin/sh
# Cargo runner for the QEMU board: boots the image on mps2-an386 and exits with its status
# (0: every decision right; 1: a decision wrong or missing; anything else: QEMU trouble).
# -icount shift=0,sleep=off: virtual time, skipped while the CPU sleeps in WFI, so the run is
# fast and the same every time. Extra arguments go to QEMU.
set -eu
elf="$1"
shift
exec qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -nographic -monitor none -serial none \
    -semihosting-config enable=on,target=native -icount shift=0,sleep=off -kernel "$elf" "$@"
