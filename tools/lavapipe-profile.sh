#!/usr/bin/env bash
# Profiles a fur command on lavapipe pass by pass. Lavapipe's timestamps misattribute
# (it bins), and perf sees its shaders only as anonymous JIT code: this runs the command
# under gdb, which logs where each shader's function is compiled, attaches perf to it
# once it is warm, and attributes the samples to the functions.
#
#   bash tools/lavapipe-profile.sh [-d DELAY_S] [-s SECONDS] -- target/release/fur render --frames 200
#
# DELAY_S (default 15): seconds before perf attaches (past start-up and the first
# frames' compiling); SECONDS (default 10): how long it records. The command must still
# be running when perf attaches and stops. Writes lavapipe-profile/ (jit.txt, perf.data,
# each function's code as code_ADDRESS.bin) and prints the shares. Needs gdb and perf
# (Debian: gdb, linux-perf); not used by the tests.
set -euo pipefail
delay=15
seconds=10
while [[ $# -gt 0 && $1 != -- ]]; do
    case $1 in
        -d) delay=$2; shift 2 ;;
        -s) seconds=$2; shift 2 ;;
        *) echo "unknown option $1 (usage: $0 [-d DELAY_S] [-s SECONDS] -- COMMAND...)" >&2; exit 2 ;;
    esac
done
[[ $# -gt 1 && $1 == -- ]] || { echo "usage: $0 [-d DELAY_S] [-s SECONDS] -- COMMAND..." >&2; exit 2; }
shift
for tool in gdb perf; do
    command -v $tool > /dev/null || { echo "$0 needs $tool" >&2; exit 1; }
done
here=$(cd "$(dirname "$0")" && pwd)
export LVP_PROFILE_OUT=$PWD/lavapipe-profile
rm -rf "$LVP_PROFILE_OUT" && mkdir -p "$LVP_PROFILE_OUT"
gdb -q -batch -x "$here/lavapipe-profile/jit.py" --args "$@" > "$LVP_PROFILE_OUT/gdb.log" 2>&1 &
gdb_pid=$!
sleep "$delay"
pid=$(pgrep -P "$gdb_pid" | head -1 || true)
if [[ -z $pid ]]; then
    echo "the command ended before perf could attach (lower -d or give it more work); see $LVP_PROFILE_OUT/gdb.log" >&2
    exit 1
fi
perf record -o "$LVP_PROFILE_OUT/perf.data" -F 999 -p "$pid" -- sleep "$seconds" > "$LVP_PROFILE_OUT/perf.log" 2>&1
wait "$gdb_pid"
python3 "$here/lavapipe-profile/attribute.py" "$LVP_PROFILE_OUT"
