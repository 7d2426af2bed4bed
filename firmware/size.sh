#!/bin/sh
# Prints `llvm-size` for both board images (build them first: `cargo firmware`, and
# `cargo qemu` or its build step) and fails if the Nucleo-L476RG release image is over budget:
# flash (text + data, where llvm-size's text includes .vector_table and .rodata) <= 48 KiB,
# static RAM (data + bss) <= 16 KiB. Run from the repository root.
set -eu
host=$(rustc -vV | sed -n 's/^host: //p')
size="$(rustc --print sysroot)/lib/rustlib/$host/bin/llvm-size"
nucleo=target/thumbv7em-none-eabihf/firmware/nucleo_l476
qemu=firmware/qemu/target/thumbv7em-none-eabihf/release/qemu
"$size" "$nucleo" "$qemu"
"$size" "$nucleo" | awk 'NR == 2 {
    flash = $1 + $2; ram = $2 + $3
    printf "nucleo_l476: flash %d B (%.1f KiB of 48), static RAM %d B (%.1f KiB of 16)\n",
        flash, flash / 1024, ram, ram / 1024
    if (flash > 48 * 1024 || ram > 16 * 1024) { print "OVER BUDGET"; exit 1 }
}'
