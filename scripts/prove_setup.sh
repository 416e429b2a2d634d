#!/usr/bin/env bash
# Proves the README's two commands on a bare Debian 12: makes a fresh Debian 12 root with
# debootstrap (minbase), copies a clean clone of this repository's HEAD into it, and runs
# `bash scripts/demo.sh` and then `bash scripts/test.sh` inside it with chroot, printing the time
# of each. Not part of CI (about 18 minutes on 2 cores with --with-shared); run it whenever setup.sh, the
# build or a dependency changes. Needs root and Debian's package registry.
#
#   bash scripts/prove_setup.sh [--root DIR] [--keep] [--with-shared] [--only demo|test]
#
#   --root DIR      where the fresh root goes (default /var/tmp/photoscene-fresh-root; removed first)
#   --keep          leave the root in place afterwards (to look at build/ or rerun by hand)
#   --with-shared   also copy ../shared (the example data) beside the clone, so the tests that use
#                   it run instead of skipping; a new user has no shared/, so the default leaves it out
#   --only STEP     run only the demo or only the test command
#   --command CMD   run CMD (in the clone, inside the root) instead of the README's commands: for
#                   a quick look, e.g. --command 'bash scripts/setup.sh && cmake -S . -B build'
#
# Commits only: uncommitted changes are not in the clone. Exit status: that of the first command
# that failed, 0 when both passed.
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROOT=/var/tmp/photoscene-fresh-root
KEEP=0
WITH_SHARED=0
ONLY=""
COMMAND=""
while [ $# -gt 0 ]; do
  case "$1" in
    --root) ROOT="$2"; shift 2 ;;
    --keep) KEEP=1; shift ;;
    --with-shared) WITH_SHARED=1; shift ;;
    --only) ONLY="$2"; shift 2 ;;
    --command) COMMAND="$2"; shift 2 ;;
    -h|--help) sed -n '2,19p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "prove_setup: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case "$ONLY" in ""|demo|test) ;; *) echo "prove_setup: --only expects demo or test, got '$ONLY'" >&2; exit 2 ;; esac
if [ "$(id -u)" -ne 0 ]; then echo "prove_setup: needs root (debootstrap, mount, chroot)" >&2; exit 2; fi

say() { echo "[prove_setup] $*"; }
MOUNTS=()
cleanup() {
  local i
  for ((i = ${#MOUNTS[@]} - 1; i >= 0; i--)); do
    umount -R "${MOUNTS[i]}" 2>/dev/null || umount -R -l "${MOUNTS[i]}" || true
  done
  if [ "$KEEP" -eq 0 ] && [ -d "$ROOT" ]; then rm -rf --one-file-system "$ROOT"; fi
}
trap cleanup EXIT

if ! command -v debootstrap >/dev/null 2>&1; then
  say "installing debootstrap"
  DEBIAN_FRONTEND=noninteractive apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
fi

# Nothing may be mounted in an old root before it is removed.
if [ -d "$ROOT" ]; then
  for m in dev/shm dev/pts dev sys/fs/cgroup sys proc; do mountpoint -q "$ROOT/$m" && umount -R -l "$ROOT/$m"; done
  rm -rf --one-file-system "$ROOT"
fi
mkdir -p "$ROOT"

t0=$(date +%s)
say "debootstrap --variant=minbase bookworm $ROOT"
debootstrap --variant=minbase bookworm "$ROOT" http://deb.debian.org/debian >"$ROOT.debootstrap.log" 2>&1 ||
  { tail -20 "$ROOT.debootstrap.log" >&2; exit 1; }
rm -f "$ROOT.debootstrap.log"
say "debootstrap: $(($(date +%s) - t0)) s"

# The registries: the same apt sources as a stock Debian 12 (updates and security included), the
# machine's DNS and certificate bundle (npm refuses the connection without them).
cat >"$ROOT/etc/apt/sources.list" <<'EOF'
deb http://deb.debian.org/debian bookworm main
deb http://deb.debian.org/debian bookworm-updates main
deb http://deb.debian.org/debian-security bookworm-security main
EOF
cp -L /etc/resolv.conf "$ROOT/etc/resolv.conf"
mkdir -p "$ROOT/etc/ssl/certs" "$ROOT/usr/local/share/ca-certificates"
cp -L /etc/ssl/certs/ca-certificates.crt "$ROOT/etc/ssl/certs/ca-certificates.crt"
# Installing Debian's ca-certificates (chromium and npm pull it in) rebuilds the bundle from
# Debian's list plus /usr/local/share/ca-certificates: the machine's own authorities must be there
# too, or they are dropped halfway through setup.
cp -L /etc/ssl/certs/ca-certificates.crt "$ROOT/usr/local/share/ca-certificates/machine-bundle.crt"
[ -f /etc/npmrc ] && cp -L /etc/npmrc "$ROOT/etc/npmrc"
# The machine's variables that name its certificate bundle or proxy (Node reads
# NODE_EXTRA_CA_CERTS, not the system store) go into the root; nothing else of this environment.
PASS_ENV=()
while IFS='=' read -r k _; do
  case "$k" in
    NODE_EXTRA_CA_CERTS|SSL_CERT_FILE|SSL_CERT_DIR|CURL_CA_BUNDLE|REQUESTS_CA_BUNDLE|http_proxy|https_proxy|no_proxy|HTTP_PROXY|HTTPS_PROXY|NO_PROXY)
      PASS_ENV+=("$k=${!k}") ;;
  esac
done < <(env)

mount -t proc proc "$ROOT/proc" && MOUNTS+=("$ROOT/proc")
mount -t sysfs sysfs "$ROOT/sys" && MOUNTS+=("$ROOT/sys")
# A booted Debian has its cgroup hierarchy mounted (slurmd refuses to start without one).
if mountpoint -q /sys/fs/cgroup; then
  # recursively (a cgroup v1 machine has one mount per controller below it), and slave so that
  # unmounting the root's copy never unmounts the machine's
  mount --rbind /sys/fs/cgroup "$ROOT/sys/fs/cgroup" && mount --make-rslave "$ROOT/sys/fs/cgroup" &&
    MOUNTS+=("$ROOT/sys/fs/cgroup")
fi
mount --bind /dev "$ROOT/dev" && MOUNTS+=("$ROOT/dev")
mount --bind /dev/pts "$ROOT/dev/pts" && MOUNTS+=("$ROOT/dev/pts")
mount -t tmpfs -o size=2g shm "$ROOT/dev/shm" && MOUNTS+=("$ROOT/dev/shm")

# A clean clone of HEAD (what CI sees), without the build folders and caches of this checkout.
mkdir -p "$ROOT/work"
git clone -q --no-hardlinks "$REPO" "$ROOT/work/main"
say "cloned $(git -C "$ROOT/work/main" log -1 --format='%h %s')"
if [ "$WITH_SHARED" -eq 1 ]; then
  [ -d "$REPO/../shared" ] || { echo "prove_setup: --with-shared but $REPO/../shared is missing" >&2; exit 2; }
  cp -a "$REPO/../shared" "$ROOT/work/shared"
  say "copied ../shared"
fi

run_in_root() {
  local name="$1" cmd="$2" start rc
  say "chroot: $cmd"
  start=$(date +%s)
  set +e
  chroot "$ROOT" /usr/bin/env -i HOME=/root TERM=dumb LANG=C.UTF-8 "${PASS_ENV[@]}" \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    /bin/bash -c "cd /work/main && $cmd" </dev/null
  rc=$?
  set -e
  TIMES+=("$(printf '%-26s %6d s   exit %d' "$cmd" "$(($(date +%s) - start))" "$rc")")
  return "$rc"
}

TIMES=()
status=0
if [ -n "$COMMAND" ]; then
  run_in_root command "$COMMAND" || status=$?
else
  if [ "$ONLY" != test ]; then run_in_root demo "bash scripts/demo.sh" || status=$?; fi
  if [ "$status" -eq 0 ] && [ "$ONLY" != demo ]; then run_in_root test "bash scripts/test.sh" || status=$?; fi
fi

say "fresh Debian 12 root, $(nproc) cores:"
for t in "${TIMES[@]}"; do echo "  $t"; done
say "total $(($(date +%s) - t0)) s, exit $status"
exit "$status"
