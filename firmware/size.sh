#!/bin/sh
# Prints `llvm-size` for both board images (build them first: `cargo firmware`, and
# `cargo qemu` or its build step) and fails if the Nucleo-L476RG image is over budget:
# flash (text + data, where llvm-size's text includes .vector_table and .rodata) <= 33 KiB,
# static RAM (data + bss) <= 8 KiB. The image was 32,492 B and 5,252 B when the budget was set
# (docs/firmware.md, "Footprint"), so a regression of about 1 KB fails CI. Run from the
# repository root.
#
# If the Nucleo image built with the `hil` feature was kept as
# target/thumbv7em-none-eabihf/firmware/nucleo_l476-hil (`.ci/run` copies it there), it is
# checked against its own budget: flash <= 40 KiB, static RAM <= 10 KiB (40,188 B and
# 9,120 B when set: the link's codec and buffers instead of the light, sensors and LEDs).
set -eu
host=$(rustc -vV | sed -n 's/^host: //p')
size="$(rustc --print sysroot)/lib/rustlib/$host/bin/llvm-size"
nucleo=target/thumbv7em-none-eabihf/firmware/nucleo_l476
hil=target/thumbv7em-none-eabihf/firmware/nucleo_l476-hil
qemu=firmware/qemu/target/thumbv7em-none-eabihf/release/qemu
"$size" "$nucleo" "$qemu"
budget() { # image, name, flash KiB, RAM KiB
    "$size" "$1" | awk -v name="$2" -v fk="$3" -v rk="$4" 'NR == 2 {
        flash = $1 + $2; ram = $2 + $3
        printf "%s: flash %d B (%.1f KiB of %d), static RAM %d B (%.1f KiB of %d)\n",
            name, flash, flash / 1024, fk, ram, ram / 1024, rk
        if (flash > fk * 1024 || ram > rk * 1024) { print "OVER BUDGET"; exit 1 }
    }'
}
budget "$nucleo" nucleo_l476 33 8
if [ -f "$hil" ]; then
    "$size" "$hil"
    budget "$hil" nucleo_l476-hil 40 10
fi
