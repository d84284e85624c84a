#!/usr/bin/env bash
# Integration test of map_server + socc-cli as real processes over UDP multicast on loopback.
# usage: service_test.sh basic|crash|auth|guard|consistency <map_server> <socc-cli>
#   basic: integrate, duplicate, chunk, stats, pose, keyframes (refused: no consistency service),
#          save/load, exports, render, clear
#   crash: kill -9 (idle and mid-run), restart with snapshot + journal -> byte-equal chunks;
#          corrupt snapshot refused unless --ignore-corrupt-snapshot
#   auth:  server with --key-file: signed CLI served, unsigned/wrong key UNAUTHENTICATED and
#          nothing changed, --auth-queries, key file readable by others refused (exit 2)
#   consistency: --consistency with snapshot + journal, kill -9, restart: the consistency
#          service resumes its stored keyframes (none twice; GET_KEYFRAMES returns them) and ends
#          with the keyframes of a server that never crashed
#   guard: a robot whose poses jump (a diverged trajectory) is refused FAILED_PRECONDITION and
#          leaves the map unchanged, another robot is served; LOST refuses until TRACKING
set -euo pipefail
mode=$1 server_bin=$2 cli_bin=$3

# shellcheck source=../integration/test_env.sh
source "$(dirname "$0")/test_env.sh"
require_multicast_on_loopback

make_work_dir
server_pid=""

url=$(random_lcm_url 30000)
echo "LCM URL: $url   work dir: $work"

fail() { echo "FAIL: $*"; [[ -f $work/server.log ]] && sed 's/^/  server: /' "$work/server.log"; exit 1; }
cli() { "$cli_bin" --lcm-url "$url" "$@"; }
expect() { # expect <pattern> <command...>: command succeeds and prints pattern
  local pattern=$1; shift
  local out
  out=$("$@" 2>&1) || fail "'$*' failed: $out"
  grep -Eq -- "$pattern" <<<"$out" || fail "'$*' printed '$out', expected /$pattern/"
  echo "ok: $* -> $(head -1 <<<"$out")"
}

probe_options=()  # socc-cli options of the start-up probe (a key when queries need one)
start_server() {
  "$server_bin" --lcm-url "$url" --file-dir "$work" "$@" >"$work/server.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 100); do
    if cli "${probe_options[@]}" --timeout-ms 100 --attempts 1 stats >/dev/null 2>&1; then return 0; fi
    kill -0 "$server_pid" 2>/dev/null || fail "map_server exited during start-up"
    sleep 0.1
  done
  fail "map_server did not answer GET_STATS within 10 s"
}
kill9_server() { kill -9 "$server_pid"; wait "$server_pid" 2>/dev/null || true; server_pid=""; }
digest() { cli chunk "$@" --digest | sed -n 's/^digest=//p'; }
integrate() { # integrate <robot> <seq> [socc-cli options]: a synthetic scan from a seq-dependent pose
  # (0.1 s per seq; at most 2.3 m and 5 deg per seq: plausible for the server's motion check)
  local robot=$1 seq=$2; shift 2
  cli --client-id "$robot" "$@" integrate --seq "$seq" --pose "$((seq / 2))" "$((seq % 3))" 0 \
    "$((seq * 5))" --seed "$seq"
}

basic() {
  start_server --quiet
  expect "seq=1 applied" integrate robot1 1
  expect "seq=2 applied" integrate robot1 2
  expect "seq=3 applied" integrate robot1 3
  expect "seq=2 duplicate" integrate robot1 2
  expect "seq=1 applied" integrate robot2 1
  expect "integrations=4 .* robots=2" cli stats
  expect "^robot1 seq=3 integrations=3" cli pose robot1
  local out; out=$(cli keyframes robot1 2>&1) && fail "GET_KEYFRAMES without --consistency: $out"
  grep -q "FAILED_PRECONDITION.*--consistency" <<<"$out" || fail "keyframes printed '$out'"
  echo "ok: cli keyframes robot1 (no --consistency) -> $(head -1 <<<"$out")"
  if cli pose ghost >/dev/null 2>&1; then fail "pose of an unknown robot succeeded"; fi
  expect "voxels=[1-9][0-9]* .*bytes=[1-9]" cli chunk --sphere 0 0 0 30 --fields features stats index
  expect "voxels=[1-9]" cli chunk --box -10 -10 -3 10 10 3
  local before; before=$(digest --sphere 0 0 0 30 --fields features stats free index)
  expect "map.snap voxels=[1-9]" cli save map.snap
  expect "map.bt voxels=[1-9]" cli export bt map.bt
  expect "map.ot voxels=[1-9]" cli export ot map.ot
  expect "map.pcd voxels=[1-9]" cli export pcd map.pcd
  for f in map.snap map.bt map.ot map.pcd; do [[ -s $work/$f ]] || fail "$f missing"; done
  expect "x" cli render --box -20 -20 -5 20 20 5 --out "$work/map.png"
  [[ $(head -c 4 "$work/map.png" | tail -c 3) == PNG ]] || fail "map.png is not a PNG"
  if cli save ../escape.snap >/dev/null 2>&1; then fail "path outside --file-dir accepted"; fi
  expect "cleared" cli clear
  expect "voxels=0 " cli stats
  expect "voxels=[1-9]" cli load map.snap
  [[ $(digest --sphere 0 0 0 30 --fields features stats free index) == "$before" ]] ||
    fail "chunk after save/clear/load differs"
  echo "ok: chunk identical after save -> clear -> load"
}

crash() {
  local durable=(--snapshot-dir "$work/snaps" --journal "$work/journal.lcmlog" --quiet)
  start_server "${durable[@]}" --snapshot-period 1
  for s in 1 2 3 4; do integrate robot1 $s >/dev/null; done
  # A periodic snapshot covers 1..4; 5..8 live only in the journal.
  for _ in $(seq 100); do [[ -s $work/snaps/map.snap ]] && break; sleep 0.1; done
  [[ -s $work/snaps/map.snap ]] || fail "no periodic snapshot written within 10 s"
  for s in 5 6 7 8; do integrate robot1 $s >/dev/null; done
  local q=(--box -30 -30 -5 30 30 5 --fields features stats free index)
  local before; before=$(digest "${q[@]}")
  kill9_server
  echo "ok: killed map_server with -9 after 8 integrations"
  start_server "${durable[@]}" --restore "$work/snaps/map.snap" --snapshot-period 1
  [[ $(digest "${q[@]}") == "$before" ]] || fail "chunk differs after kill -9 + restore"
  echo "ok: byte-equal chunk after kill -9 and snapshot + journal restore"
  expect "seq=8 duplicate" integrate robot1 8
  expect "^robot1 seq=8 integrations=8" cli pose robot1

  # Mid-run: kill -9 while a client streams scans, restart, let the client resend everything
  # (duplicates are acknowledged, the rest applied) and compare with a server that never crashed.
  ( for s in $(seq 9 30); do
      integrate robot1 "$s" --timeout-ms 300 --attempts 1 >/dev/null 2>&1 || break
    done ) &
  local streamer=$!
  sleep 0.4
  kill9_server
  wait "$streamer" || true
  start_server "${durable[@]}" --restore "$work/snaps/map.snap" --snapshot-period 1
  for s in $(seq 1 30); do integrate robot1 "$s" >/dev/null || fail "resend of seq $s failed"; done
  local crashed; crashed=$(digest "${q[@]}")
  kill9_server
  start_server --quiet
  for s in $(seq 1 30); do integrate robot1 "$s" >/dev/null; done
  [[ $(digest "${q[@]}") == "$crashed" ]] || fail "map after mid-run kill -9 differs from a clean run"
  echo "ok: mid-run kill -9 + resend equals an uninterrupted run"
  kill9_server

  # A damaged snapshot is refused with a clear error; --ignore-corrupt-snapshot starts empty.
  printf 'garbage' | dd of="$work/snaps/map.snap" bs=1 seek=300 conv=notrunc status=none
  if "$server_bin" --lcm-url "$url" "${durable[@]}" --restore "$work/snaps/map.snap" \
      >"$work/corrupt.log" 2>&1; then
    fail "map_server started from a corrupt snapshot"
  fi
  grep -q "cannot restore" "$work/corrupt.log" || fail "no clear error: $(cat "$work/corrupt.log")"
  echo "ok: corrupt snapshot refused: $(head -1 "$work/corrupt.log")"
  start_server "${durable[@]}" --restore "$work/snaps/map.snap" --ignore-corrupt-snapshot
  expect "voxels=0 " cli stats
  ls "$work/snaps" | grep -q "corrupt-" || fail "corrupt snapshot was not set aside"
}

expect_refused() { # expect_refused <pattern> <command...>: command fails and prints pattern
  local pattern=$1; shift
  local out
  if out=$("$@" 2>&1); then fail "'$*' succeeded: $out"; fi
  grep -Eq -- "$pattern" <<<"$out" || fail "'$*' printed '$out', expected /$pattern/"
  echo "ok: refused: $* -> $(head -1 <<<"$out")"
}

auth() {
  local key=$work/map.key wrong=$work/wrong.key
  new_key() { (umask 077 && head -c 32 /dev/urandom | od -An -tx1 | tr -d ' \n' >"$1"); }
  new_key "$key"
  new_key "$wrong"
  start_server --quiet --key-file "$key"
  expect "seq=1 applied" integrate robot1 1 --key-file "$key"
  expect "seq=2 applied" integrate robot1 2 --key-file "$key"
  local before; before=$(digest --sphere 0 0 0 30 --fields features stats free index)
  expect_refused "UNAUTHENTICATED.*not signed" integrate robot1 3
  expect_refused "UNAUTHENTICATED.*not signed" integrate robot2 1
  expect_refused "UNAUTHENTICATED.*mac does not match" integrate robot1 3 --key-file "$wrong"
  expect_refused "UNAUTHENTICATED" cli clear
  expect_refused "UNAUTHENTICATED" cli save map.snap
  [[ -e $work/map.snap ]] && fail "unsigned save wrote a file"
  [[ $(digest --sphere 0 0 0 30 --fields features stats free index) == "$before" ]] ||
    fail "map changed by refused requests"
  expect "integrations=2 .*auth_failures=5 robots=1" cli stats
  expect "map.snap voxels=[1-9]" cli --key-file "$key" save map.snap
  expect "cleared" cli --key-file "$key" clear
  expect "voxels=0 " cli stats
  kill9_server

  # --auth-queries: reads need the key too.
  probe_options=(--key-file "$key")
  start_server --quiet --key-file "$key" --auth-queries
  expect_refused "UNAUTHENTICATED" cli stats
  expect "voxels=0 " cli --key-file "$key" stats
  kill9_server
  probe_options=()

  # A key that group or others can read is refused at start with a clear error and exit 2.
  chmod 0644 "$key"
  local rc=0
  "$server_bin" --lcm-url "$url" --key-file "$key" --quiet >"$work/perm.log" 2>&1 || rc=$?
  [[ $rc == 2 ]] || fail "map_server with a 0644 key file exited $rc: $(cat "$work/perm.log")"
  grep -q "chmod" "$work/perm.log" || fail "no clear key file error: $(cat "$work/perm.log")"
  echo "ok: 0644 key file refused (exit 2): $(head -1 "$work/perm.log")"
  expect_refused "chmod" cli --key-file "$key" stats
}

car2() { cli --client-id car2 "$@"; }

# The same accepted scans in the same order as guard() below, on a fresh server.
guard_reference() {
  for s in 1 2; do integrate robot1 "$s" >/dev/null; done
  car2 integrate --seq 1 --pose 3 0 0 0 --seed 101 >/dev/null
  for s in 3 4 5 6; do integrate robot1 "$s" >/dev/null; done
  car2 integrate --seq 8 --pose 40 0 0 0 --seed 108 >/dev/null
}

guard() {
  local q=(--sphere 0 0 0 60 --fields features stats free index)
  start_server --quiet
  for s in 1 2; do expect "seq=$s applied" integrate robot1 "$s"; done
  expect "seq=1 applied" car2 integrate --seq 1 --pose 3 0 0 0 --seed 101
  local before; before=$(digest "${q[@]}")
  # car2 diverges: 25 m further per 0.1 s. Each pose is judged against its last accepted one.
  for s in 2 3 4 5 6; do
    expect_refused "FAILED_PRECONDITION: pose jumps .* m/s > max 40 m/s\) from robot car2's last accepted pose \(seq 1\)" \
      car2 integrate --seq "$s" --pose "$((25 * s))" 0 0 0 --seed "$((100 + s))"
  done
  [[ $(digest "${q[@]}") == "$before" ]] || fail "refused integrations changed the map"
  echo "ok: map digest unchanged by 5 refused integrations"
  expect "^car2 seq=1 integrations=1 .* tracking=TRACKING refused=5" cli pose car2
  for s in 3 4 5 6; do expect "seq=$s applied" integrate robot1 "$s"; done

  # car2 reports LOST: refused whatever its pose, until it reports TRACKING (relocalized), and
  # its next pose is then a new start.
  expect 'tracking=LOST refused=5 reported_at_seq=6 reason="diverged"' \
    car2 tracking LOST --seq 6 --reason diverged
  expect_refused "FAILED_PRECONDITION: robot car2 reported LOST at seq 6 \(diverged\)" \
    car2 integrate --seq 7 --pose 3 0 0 0 --seed 107
  expect "tracking=TRACKING refused=6" car2 tracking TRACKING --seq 7
  expect "seq=8 applied" car2 integrate --seq 8 --pose 40 0 0 0 --seed 108
  expect "integrations=8 .*robots=2" cli stats
  local guarded; guarded=$(digest "${q[@]}")
  kill9_server

  # The reference server takes every scan (the check off, from the config: car2's 8 is far
  # from its 1, which the guarded server only accepted after the relocalization).
  printf 'plausibility:\n  enabled: false\n' >"$work/open.yaml"
  start_server --quiet --config "$work/open.yaml"
  guard_reference
  [[ $(digest "${q[@]}") == "$guarded" ]] || fail "map differs from one without the refused scans"
  echo "ok: map equals a server that only ever saw the accepted scans"
}

stop_server() { kill -TERM "$server_pid"; wait "$server_pid" 2>/dev/null || true; server_pid=""; }
keyframe_seqs() { cut -d' ' -f1,2 "$1/keyframes.txt"; }

consistency() {
  local durable=(--consistency --snapshot-dir "$work/snaps" --journal "$work/journal.lcmlog")
  start_server "${durable[@]}" --snapshot-period 1
  for s in $(seq 1 12); do integrate robot1 "$s" >/dev/null; done
  sleep 1.5  # a periodic snapshot marks the store; the worker stores the keyframes
  for s in $(seq 13 16); do integrate robot1 "$s" >/dev/null; done
  kill9_server
  [[ -s $work/snaps/map.snap.consistency ]] || fail "no consistency store beside the snapshot"
  start_server "${durable[@]}" --restore "$work/snaps/map.snap" --consistency-dir "$work/crashed"
  grep -Eq "consistency state restored: [1-9][0-9]* keyframes" "$work/server.log" ||
    fail "the consistency state was not restored"
  echo "ok: $(grep -o 'consistency state restored: [0-9]* keyframes' "$work/server.log") after kill -9"
  for s in $(seq 17 24); do integrate robot1 "$s" >/dev/null; done
  # GET_KEYFRAMES: the optimized keyframes, those from before the kill among them.
  expect "^robot1: [1-9][0-9]* keyframes \(seq 1 to" cli keyframes robot1 --kitti "$work/kf.txt"
  [[ -s $work/kf.txt ]] || fail "socc-cli keyframes --kitti wrote nothing"
  stop_server
  [[ -z $(keyframe_seqs "$work/crashed" | sort | uniq -d) ]] || fail "a keyframe stored twice"
  start_server --consistency --consistency-dir "$work/clean" --quiet
  for s in $(seq 1 24); do integrate robot1 "$s" >/dev/null; done
  stop_server
  [[ $(keyframe_seqs "$work/crashed") == $(keyframe_seqs "$work/clean") ]] ||
    fail "keyframes after kill -9 + restart differ from a clean run"
  echo "ok: $(wc -l <"$work/clean/keyframes.txt") keyframes, the same as a server that never crashed"
}

"$mode"
echo "PASS: $mode"
