#!/usr/bin/env bash
# A stop signal while linx reads its input (docs/reliability.md, "Signals"): `linx check`, `run`
# and `convert` of a scene whose mesh takes seconds to read stop within a second of SIGINT or
# SIGTERM, with exit status 130, one line naming the input, and nothing written. And reading
# stays linear in the size of the input: an OBJ of one face of 400,000 vertices (10 MB), which
# kept `linx check` busy for minutes, is refused at once.
#   test_load_interrupt.sh LINX
set -u
linx=$(realpath "$1")

work=$(mktemp -d "${TMPDIR:-/tmp}/linx_load_interrupt.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1

fail() {
  echo "FAIL: $*" >&2
  echo "--- stderr:" >&2
  cat err.txt >&2 2>/dev/null
  exit 1
}

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }

# A terrain of 800 x 800 vertices (1.3 million triangles, 39 MB): 4 s to read and check.
awk 'BEGIN {
  n = 800
  for (i = 0; i < n; ++i) for (j = 0; j < n; ++j) printf "v %d %d %.3f\n", i, j, (i * j % 7) / 10
  for (i = 0; i < n - 1; ++i) for (j = 0; j < n - 1; ++j) {
    a = i * n + j + 1
    printf "f %d %d %d\nf %d %d %d\n", a, a + n, a + 1, a + 1, a + n, a + n + 1
  }
}' >terrain.obj
cat >big.json <<'EOF'
{
  "duration": 0.01,
  "bodies": [{"name": "terrain", "static": true, "shapes": [{"type": "mesh", "file": "terrain.obj"}]},
             {"name": "ball", "position": [5, 5, 2], "shapes": [{"type": "sphere", "radius": 0.1, "density": 500}]}]
}
EOF

# interrupt SIGNAL OUTPUT CMD...: starts CMD, sends SIGNAL after 0.5 s, and checks that it ends
# within 1.5 s of it with exit status 130, its message, and no OUTPUT written.
interrupt() {
  local signal=$1 output=$2
  shift 2
  "$@" >/dev/null 2>err.txt &
  local pid=$!
  sleep 0.5
  kill -0 "$pid" 2>/dev/null || fail "'$*' ended before the signal: the input reads too fast"
  local sent
  sent=$(now)
  kill -"$signal" "$pid"
  wait "$pid"
  local status=$? took
  took=$(elapsed "$sent" "$(now)")
  [ "$status" -eq 130 ] || fail "SIG$signal to '$*': exit status $status, expected 130"
  awk -v t="$took" 'BEGIN { exit !(t < 1.5) }' ||
    fail "SIG$signal to '$*': ended $took s after the signal, expected within 1.5 s"
  [ "$(cat err.txt)" = "linx: big.json: interrupted while reading it; nothing written" ] ||
    fail "SIG$signal to '$*': unexpected message"
  [ ! -e "$output" ] || fail "SIG$signal to '$*': $output was written"
  echo "SIG$signal to '$*': exit 130, $took s after the signal"
}

# (Each command is checked to be still reading when the signal goes: else it proves nothing.)
interrupt INT out "$linx" check big.json
interrupt TERM out "$linx" check big.json
interrupt INT out "$linx" run big.json --out out
interrupt INT out.json "$linx" convert big.json out.json

# One face of 400,000 vertices: refused (the bound on vertices per face) in well under 5 s.
awk 'BEGIN {
  n = 400000
  for (i = 0; i < n; ++i) printf "v %.6f %.6f 0\n", cos(6.283185307 * i / n), sin(6.283185307 * i / n)
  printf "f"
  for (i = 1; i <= n; ++i) printf " %d", i
  printf "\n"
}' >face.obj
sed 's/terrain.obj/face.obj/' big.json >face.json
start=$(now)
timeout 60 "$linx" check face.json >/dev/null 2>err.txt
status=$?
took=$(elapsed "$start" "$(now)")
[ "$status" -eq 2 ] || fail "face.json: exit status $status, expected 2"
grep -q "face.obj: OBJ line 400001: a face of 400000 vertices, above the limit of 64" err.txt ||
  fail "face.json: unexpected message"
awk -v t="$took" 'BEGIN { exit !(t < 5) }' || fail "face.json: refused after $took s, expected < 5 s"
echo "one face of 400000 vertices: refused in $took s"
# Includes bounded in bytes over the whole model: a file of 1 MiB included 70 times.
{
  echo '<mujoco>'
  head -c 1048576 /dev/zero | tr '\0' ' '
  echo '</mujoco>'
} >mib.xml
{
  echo '<mujoco model="bytes">'
  for _ in $(seq 70); do echo '  <include file="mib.xml"/>'; done
  echo '</mujoco>'
} >bytes.xml
"$linx" check bytes.xml >/dev/null 2>err.txt
status=$?
[ "$status" -eq 2 ] || fail "bytes.xml: exit status $status, expected 2"
[ "$(cat err.txt)" = "linx: bytes.xml: include (line 65): file 'mib.xml': the model and the includes read reach 67112073 bytes, above the limit of 67108864 for a whole model" ] ||
  fail "bytes.xml: unexpected message"
echo "ok"
