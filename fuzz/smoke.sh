#!/usr/bin/env bash
# Fuzz smoke test of the protocol crate and the HIL link: runs every cargo-fuzz target (the ten
# of `cargo fuzz list`) for FUZZ_SECONDS seconds (default 60, each target in turn, never in
# parallel) on a throwaway copy of its seed corpus,
# so the committed corpus/ is never changed. Exits non-zero if any target crashes, hangs (an
# input running over 10 s) or runs out of memory; the input that did is kept under
# fuzz/artifacts/<target>/ (see README.md, "Replaying a crash").
#
# Needs a nightly toolchain (cargo-fuzz builds with -Z flags); without one it says so and
# exits 0. Installs cargo-fuzz if it is missing. Runs from any directory.
#
#   fuzz/smoke.sh                              all targets, 60 s each
#   FUZZ_SECONDS=300 fuzz/smoke.sh             longer runs
#   FUZZ_TARGETS="deframer roundtrip" fuzz/smoke.sh
#   FUZZ_SEED=7 fuzz/smoke.sh                  libFuzzer's seed (default 1; 0 = libFuzzer picks)
#   FUZZ_WORK=fuzz/work fuzz/smoke.sh          keep the working corpora and logs there
#                                              (default: a temporary directory, removed)
#   FUZZ_SKIP_TESTS=1 fuzz/smoke.sh            skip `cargo test` of the fuzz crate
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"

if ! command -v rustup >/dev/null 2>&1 || ! rustup toolchain list | grep -q nightly; then
    echo "nightly not present: fuzz smoke skipped"
    exit 0
fi

if ! command -v cargo-fuzz >/dev/null 2>&1; then
    echo "installing cargo-fuzz"
    cargo install cargo-fuzz --locked || cargo install cargo-fuzz
fi

seconds=${FUZZ_SECONDS:-60}
case "$seconds" in
'' | *[!0-9]*)
    echo "FUZZ_SECONDS must be a whole number of seconds, not '$seconds'" >&2
    exit 2
    ;;
esac
seed=${FUZZ_SEED:-1}
case "$seed" in
'' | *[!0-9]*)
    echo "FUZZ_SEED must be a whole number, not '$seed'" >&2
    exit 2
    ;;
esac

if [ -n "${FUZZ_WORK:-}" ]; then
    work=$FUZZ_WORK
    mkdir -p "$work"
    work=$(cd "$work" && pwd)
else
    work=$(mktemp -d "${TMPDIR:-/tmp}/protocol-fuzz.XXXXXX")
    trap 'rm -rf "$work"' EXIT
fi

# The checks themselves and the corpus: the committed seeds are what corpus.rs generates, and
# each passes its check (pinned toolchain, no libFuzzer involved).
if [ -z "${FUZZ_SKIP_TESTS:-}" ]; then
    cargo test --quiet
fi

targets=${FUZZ_TARGETS:-$(cargo +nightly fuzz list)}
cargo +nightly fuzz build

failed=()
summary=()
for t in $targets; do
    if [ ! -d "corpus/$t" ]; then
        echo "no seed corpus for target '$t' (corpus/$t)" >&2
        exit 2
    fi
    rm -rf "${work:?}/$t"
    mkdir -p "$work/$t"
    cp corpus/"$t"/* "$work/$t/"
    log="$work/$t.log"
    echo "fuzzing $t for ${seconds}s (seed $seed)"
    if cargo +nightly fuzz run "$t" "$work/$t" -- \
        -max_total_time="$seconds" -timeout=10 -seed="$seed" -print_final_stats=1 >"$log" 2>&1; then
        status=ok
    else
        status=FAILED
        failed+=("$t")
        echo "---- $t failed; the end of its log ($log):"
        tail -n 60 "$log"
        echo "----"
    fi
    done_line=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | tail -n 1 || true)
    summary+=("$(printf '%-15s %-7s %s' "$t" "$status" "${done_line:-(no DONE line)}")")
done

echo
echo "fuzz smoke, ${seconds}s per target:"
printf '  %s\n' "${summary[@]}"
if [ ${#failed[@]} -gt 0 ]; then
    echo "FAILED: ${failed[*]} (inputs under fuzz/artifacts/; see fuzz/README.md)" >&2
    exit 1
fi
echo "all targets ran clean"
