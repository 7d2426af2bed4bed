#!/usr/bin/env bash
# Submits a sharded `cimax arena sweep` to Slurm: a job array of N shards (sweep.sbatch) and a
# merge (merge.sbatch) that runs only if every shard succeeded. See docs/scale.md.
#
#   scripts/slurm/submit.sh --shards 8 --parts /shared/run1/parts --out /shared/run1/figs \
#       -- --field sharp --robots 1000 --runs 10
#
# Options (before `--`; after it, the sweep's own options, without --out and --shard):
#   --shards N          number of shards, 1 to 1000 (required)
#   --parts DIR         folder for part-I-of-N.jsonl and the jobs' logs (DIR/logs); on a
#                       filesystem every node sees (required). Refused if it holds parts already,
#                       unless --missing or --only.
#   --out DIR           folder for the merged CSV and SVG (required)
#   --missing           submit only the shards whose part is not in DIR yet (resuming), then merge
#   --only LIST         submit only these shards (a Slurm array list: 2,5 or 3-7), then merge
#   --time T            time limit of each shard (sbatch --time; default: sweep.sbatch's)
#   --sbatch OPT        an extra sbatch option for both jobs, repeatable
#                       (--sbatch --partition=short --sbatch --account=proj42 --sbatch --mem=2G)
#   --wait              wait until the merge has ended; exit with its status
# Environment: CIMAX (the binary; default cimax on PATH, resolved here to an absolute path, which
# must exist on the nodes too), CIMAX_SUBCOMMAND (default "arena sweep"), and sbatch's own
# SBATCH_PARTITION, SBATCH_ACCOUNT, SBATCH_QOS, ... which apply to both jobs.
# Prints the two job ids, one per line, as `array JOBID` and `merge JOBID`.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
die() {
    echo "submit.sh: $*" >&2
    exit 2
}

shards="" parts="" out="" only="" missing=0 wait=0 time=""
extra=()
while [ $# -gt 0 ]; do
    case "$1" in
    --shards) shards=${2:?--shards needs N} && shift 2 ;;
    --parts) parts=${2:?--parts needs a folder} && shift 2 ;;
    --out) out=${2:?--out needs a folder} && shift 2 ;;
    --only) only=${2:?--only needs a list} && shift 2 ;;
    --missing) missing=1 && shift ;;
    --time) time=${2:?--time needs a limit} && shift 2 ;;
    --sbatch) extra+=("${2:?--sbatch needs an option}") && shift 2 ;;
    --wait) wait=1 && shift ;;
    --) shift && break ;;
    -h | --help) sed -n '2,/^set -euo/{/^set -euo/d;s/^# \{0,1\}//;p}' "$0" && exit 0 ;;
    *) die "unknown option $1 (the sweep's options go after --)" ;;
    esac
done
if ! [[ "$shards" =~ ^[1-9][0-9]{0,3}$ && "$shards" -le 1000 ]]; then die "--shards N, 1 to 1000"; fi
[ -n "$parts" ] || die "--parts DIR is required"
[ -n "$out" ] || die "--out DIR is required"
[ -z "$only" ] || [ "$missing" = 0 ] || die "--only and --missing exclude each other"
command -v sbatch >/dev/null || die "sbatch not found: is this a Slurm login node?"

cimax=${CIMAX:-cimax}
if [[ "$cimax" == */* ]]; then
    [ -x "$cimax" ] || die "CIMAX=$cimax is not an executable"
    cimax=$(cd "$(dirname "$cimax")" && pwd)/$(basename "$cimax")
else
    cimax=$(command -v "$cimax") || die "$cimax is not on PATH: set CIMAX=/path/to/cimax (on a filesystem the nodes see)"
fi

mkdir -p "$parts/logs" "$out"
parts=$(cd "$parts" && pwd)
out=$(cd "$out" && pwd)

array="1-$shards"
if [ "$missing" = 1 ]; then
    list=()
    for i in $(seq 1 "$shards"); do
        [ -e "$parts/part-$i-of-$shards.jsonl" ] || list+=("$i")
    done
    array=$(
        IFS=,
        echo "${list[*]}"
    )
    echo "missing shards: ${array:-none}" >&2
elif [ -n "$only" ]; then
    array=$only
else
    shopt -s nullglob
    old=("$parts"/part-*.jsonl)
    [ "${#old[@]}" = 0 ] || die "$parts holds ${#old[@]} parts already: resume with --missing, or use a fresh folder"
fi

export PARTS=$parts OUT=$out SHARDS=$shards CIMAX=$cimax
dependency=()
if [ -n "$array" ]; then
    opts=(--parsable --export=ALL --array="$array" --output="$parts/logs/sweep-%A_%a.log")
    [ -z "$time" ] || opts+=(--time="$time")
    array_job=$(sbatch "${opts[@]}" "${extra[@]}" "$here/sweep.sbatch" "$@")
    array_job=${array_job%%;*}
    echo "array $array_job"
    echo "shards $array of $shards: logs $parts/logs/sweep-${array_job}_*.log" >&2
    dependency=(--dependency="afterok:$array_job" --kill-on-invalid-dep=yes)
fi

opts=(--parsable --export=ALL --output="$parts/logs/merge-%j.log")
merge_job=$(sbatch "${opts[@]}" "${dependency[@]}" "${extra[@]}" "$here/merge.sbatch")
merge_job=${merge_job%%;*}
echo "merge $merge_job"
echo "merge (after every shard succeeds): $parts/logs/merge-$merge_job.log, into $out" >&2
[ "$wait" = 1 ] || exit 0

# --wait: poll the merge's state (sbatch --wait cannot be trusted here: it exits 0 for a merge
# that Slurm cancelled because a shard failed).
state() {
    local s
    s=$(scontrol show job -o "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -n 1) || true
    [ -n "$s" ] || s=JobState=$(sacct -n -X -P -j "$1" -o State 2>/dev/null | head -n 1 | cut -d' ' -f1) || true
    echo "${s#JobState=}"
}
while :; do
    s=$(state "$merge_job")
    case "$s" in
    PENDING | CONFIGURING | RUNNING | COMPLETING | SUSPENDED | REQUEUED | RESIZING) sleep "${SUBMIT_POLL_S:-2}" ;;
    *) break ;;
    esac
done
[ "$s" = COMPLETED ] && exit 0
echo "submit.sh: the merge ended ${s:-in an unknown state (purged: see its log)}" >&2
if [ -n "${array_job:-}" ]; then
    scontrol show job -o "$array_job" 2>/dev/null | grep -v 'JobState=COMPLETED' |
        grep -o 'ArrayTaskId=[^ ]* JobName=[^ ]*\|JobState=[A-Z_]*\|ExitCode=[^ ]*' | paste -d' ' - - - >&2 || true
fi
exit 1
