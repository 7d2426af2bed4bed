#!/bin/sh
# Prints `llvm-size` for both board images (build them first: `cargo firmware`, and
# `cargo qemu` or its build step) and fails if the Nucleo-L476RG image is over budget:
# flash (text + data, where llvm-size's text includes .vector_table and .rodata) <= 33 KiB,
# static RAM (data + bss) <= 8 KiB. The image was 32,492 B and 5,252 B when the budget was set
# (docs/firmware.md, "Footprint"), so a regression of about 1 KB fails CI. Run from the
# repository root.
set -eu
host=$(rustc -vV | sed -n 's/^host: //p')
size="$(rustc --print sysroot)/lib/rustlib/$host/bin/llvm-size"
nucleo=target/thumbv7em-none-eabihf/firmware/nucleo_l476
qemu=firmware/qemu/target/thumbv7em-none-eabihf/release/qemu
"$size" "$nucleo" "$qemu"
"$size" "$nucleo" | awk 'NR == 2 {
    flash = $1 + $2; ram = $2 + $3
    printf "nucleo_l476: flash %d B (%.1f KiB of 33), static RAM %d B (%.1f KiB of 8)\n",
        flash, flash / 1024, ram, ram / 1024
    if (flash > 33 * 1024 || ram > 8 * 1024) { print "OVER BUDGET"; exit 1 }
}'
