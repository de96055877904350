#!/usr/bin/env bash
# Runs the README's two commands on a clean Debian 13 ("trixie") system, in a chroot.
#
#   sudo tools/check-debian13.sh [DIR]        # DIR defaults to /var/tmp/fur-trixie
#
# What it does, in order:
#   1. `debootstrap --variant=minbase trixie DIR MIRROR` (once; MIRROR is the host's Debian
#      mirror, or $MIRROR), then binds /proc, /sys and /dev into it and copies the host's
#      DNS settings and extra CA certificates (a proxy's, if the host needs one);
#   2. copies this working tree (tracked and untracked files, not `target/`) to DIR/root/fur;
#   3. Rust: with FUR_RUST=host (the default when the host has rustup toolchains) the
#      host's ~/.rustup is bound read-only and its ~/.cargo/bin copied in; with
#      FUR_RUST=rustup the README's own command fetches rustup inside the chroot;
#   4. runs the README's first command (the "Quick start" block, `sudo ` dropped: the
#      chroot is root) and checks that it wrote `fur.png`, then the README's test command.
#
# Not part of CI (a clean build and the whole suite take about 40 minutes on 2 cores; a
# later run reuses the chroot's build folder).
# Options through the environment: MIRROR, FUR_RUST=host|rustup, TEST_ARGS (appended to the
# test command, e.g. `-- --test-threads 1`), KEEP_MOUNTS=1 to leave the binds mounted.
set -euo pipefail

ROOT=${1:-/var/tmp/fur-trixie}
REPO=$(cd "$(dirname "$0")/.." && pwd)
if [ "$(id -u)" != 0 ]; then
    echo "check-debian13: run as root (debootstrap and chroot need it)" >&2
    exit 2
fi
if [ -z "${MIRROR:-}" ]; then
    MIRROR=$(grep -rhoE '(URIs:|deb) +https?://[^ ]+/debian/?( |$)' /etc/apt/sources.list \
        /etc/apt/sources.list.d/ 2>/dev/null | head -n1 | awk '{print $2}' || true)
    MIRROR=${MIRROR:-http://deb.debian.org/debian}
fi
if [ -z "${FUR_RUST:-}" ]; then
    if [ -d "$HOME/.rustup/toolchains" ] && [ -x "$HOME/.cargo/bin/cargo" ]; then
        FUR_RUST=host
    else
        FUR_RUST=rustup
    fi
fi

command -v debootstrap >/dev/null || {
    apt-get update -qq && apt-get install -y -qq debootstrap >/dev/null
}
if [ ! -x "$ROOT/usr/bin/apt-get" ]; then
    echo "== debootstrap trixie into $ROOT from $MIRROR"
    mkdir -p "$ROOT"
    debootstrap --variant=minbase trixie "$ROOT" "$MIRROR" >"$ROOT.debootstrap.log" 2>&1 || {
        tail -n 20 "$ROOT.debootstrap.log" >&2
        exit 1
    }
fi

MOUNTS=()
unmount_all() {
    [ "${KEEP_MOUNTS:-0}" = 1 ] && return
    local i
    for ((i = ${#MOUNTS[@]} - 1; i >= 0; i--)); do
        umount -l "${MOUNTS[$i]}" 2>/dev/null || true
    done
}
trap unmount_all EXIT
bind() { # bind SRC DST [ro]
    mkdir -p "$2"
    if ! mountpoint -q "$2"; then
        mount --bind "$1" "$2"
        [ "${3:-}" = ro ] && mount -o remount,bind,ro "$2"
        MOUNTS+=("$2")
    fi
}
bind /proc "$ROOT/proc"
bind /sys "$ROOT/sys"
bind /dev "$ROOT/dev"
cp -L /etc/resolv.conf "$ROOT/etc/resolv.conf"
mkdir -p "$ROOT/usr/local/share/ca-certificates"
cp /usr/local/share/ca-certificates/*.crt "$ROOT/usr/local/share/ca-certificates/" 2>/dev/null || true

echo "== copying the working tree to $ROOT/root/fur"
# A fresh copy each run; the build folder of an earlier run is kept (incremental builds).
mkdir -p "$ROOT/root/fur"
find "$ROOT/root/fur" -mindepth 1 -maxdepth 1 ! -name target -exec rm -rf {} +
(cd "$REPO" && git ls-files -co --exclude-standard -z | tar --null -T - -cf -) |
    tar -C "$ROOT/root/fur" -xf -

if [ "$FUR_RUST" = host ]; then
    echo "== Rust: the host's toolchains (bound read-only), cargo's binaries copied"
    bind "$HOME/.rustup" "$ROOT/root/.rustup" ro
    mkdir -p "$ROOT/root/.cargo"
    cp -a "$HOME/.cargo/bin" "$ROOT/root/.cargo/"
else
    echo "== Rust: rustup, as the README's command installs it"
fi

# The README's blocks under "Quick start": the first sets up and renders, the second tests.
readme_block() { # readme_block N  -> the Nth ```sh block of the Quick start section
    awk -v want="$1" '
        /^## / { inside = ($0 ~ /^## Quick start/) }
        inside && /^```sh/ { n++; grab = (n == want); next }
        /^```/ { grab = 0; next }
        grab { print }' "$REPO/README.md"
}
SETUP=$(readme_block 1 | sed 's/\bsudo //g')
TEST=$(readme_block 2)
[ -n "$SETUP" ] && [ -n "$TEST" ] || {
    echo "check-debian13: could not find the two commands under README's 'Quick start'" >&2
    exit 1
}

run_in() { # run_in "command": a login-like root shell in the chroot, in the copied tree
    chroot "$ROOT" /usr/bin/env -i HOME=/root TERM=dumb PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
        RUSTUP_AUTO_INSTALL=0 SSL_CERT_FILE=/etc/ssl/certs/ca-certificates.crt \
        bash -c "cd /root/fur && $1"
}
# apt's own first run inside a minbase chroot: nothing is installed that the README's
# command does not install itself, except what running a bash script needs (it has it).
echo "== Debian $(cat "$ROOT/etc/debian_version") in $ROOT"
echo "== README command 1: $SETUP"
run_in "$SETUP"
run_in 'test -s fur.png && head -c 8 fur.png | od -An -c | grep -q "P   N   G"' || {
    echo "check-debian13: the first command did not write fur.png" >&2
    exit 1
}
echo "== fur.png written"
echo "== README command 2: $TEST ${TEST_ARGS:-}"
run_in "export PATH=\$HOME/.cargo/bin:\$PATH && $TEST ${TEST_ARGS:-}"
echo "== Debian 13: both README commands passed"
