#!/usr/bin/env bash
# Names, folder names and paths that would be code in an output language stay data (issue 43):
# a scene whose joints and bodies are named with backquotes, $(...), @macros, quotes, newlines,
# terminal escapes and odd code points is checked, run, plotted (gnuplot), rendered (POV-Ray) and
# exported (VTK) into a folder whose own name holds backquotes; so is a run folder crafted by hand.
# No command in a name ever runs (the canary files never appear), the plot titles show the names
# (read back from the SVG), and nothing linx prints holds a control character.
# Usage: test_hostile_names.sh LINX
set -u
linx=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
canary="$work/CANARY"
# Every file linx writes here, and its messages, are checked for a canary after each command.
no_canary() {
  local found
  found=$(find "$work" -type f -name 'CANARY*' | head -1)
  [ -z "$found" ] || fail "$1 ran a command from a name: $found exists"
}
# Nothing printed holds a control character other than the line ends (ESC would act).
clean_output() {
  if LC_ALL=C grep -q -P '[\x00-\x09\x0b-\x1f\x7f]' "$1"; then
    fail "$2 printed a control character: $(od -c "$1" | head -5)"
  fi
}

python3 - "$canary" <<'PY' || fail "cannot write the scene"
import json, sys
c = sys.argv[1]
names = {
    "j0": f"pivot`touch {c}1` > owned",
    "j1": f"$(touch {c}2) @m \"q\" 'x' \\ %s `touch {c}3`",
    "b0": "up\nper\x1b[2J\x1b]0;title\x07",
    "b1": "low\u202eer \u00e9\u65e5 #declare X=1; */ /* \u0085 \x7f",
}
scene = {
    "gravity": [0, 0, -9.81], "timestep": 0.001, "duration": 0.05,
    "bodies": [
        {"name": names["b0"], "mass": 1, "position": [0.5, 0, 0],
         "shapes": [{"type": "box", "size": [1, 0.05, 0.05]}]},
        {"name": names["b1"], "mass": 1, "position": [1.5, 0, 0],
         "shapes": [{"type": "sphere", "radius": 0.1}]},
    ],
    "joints": [
        {"name": names["j0"], "type": "hinge", "body1": names["b0"], "anchor": [0, 0, 0],
         "axis": [0, 1, 0]},
        {"name": names["j1"], "type": "hinge", "body1": names["b0"], "body2": names["b1"],
         "anchor": [1, 0, 0], "axis": [0, 1, 0]},
    ],
}
json.dump(scene, open("scene.json", "w"))
json.dump(names, open("names.json", "w"))
PY

# A folder name with backquotes and $(...): it reaches the plot script's comment line (the
# commands would run in the folder's plots/ or render/, where no_canary looks too).
out="out\`touch CANARY4\`\$(touch CANARY5)"

"$linx" check scene.json >check.txt 2>&1 || fail "linx check: $(cat check.txt)"
clean_output check.txt "linx check"
"$linx" run scene.json --out "$out" >run.txt 2>&1 || fail "linx run: $(cat run.txt)"
clean_output run.txt "linx run"
no_canary "linx run"

"$linx" plot "$out" >plot.txt 2>&1 || fail "linx plot: $(cat plot.txt)"
clean_output plot.txt "linx plot"
no_canary "linx plot"
# The titles show the names (and `(hinge)`), as gnuplot drew them into the SVG.
python3 - "$out/plots/joint_coordinates.svg" <<'PY' || fail "linx plot: the titles do not show the names"
import json, sys
import xml.etree.ElementTree as ET
names = json.load(open("names.json"))
texts = ["".join(e.itertext()) for e in ET.parse(sys.argv[1]).iter() if e.tag.endswith("text")]
for key in ("j0", "j1"):
    want = names[key] + " (hinge)"
    if want not in texts:
        sys.exit(f"{want!r} not among {texts}")
PY
# The script's only backquotes are in its comment line; the folder there is a quoted literal.
[ "$(grep -c '`' "$out/plots/plots.gp")" = 1 ] || fail "plots.gp: backquotes outside the comment"
head -1 "$out/plots/plots.gp" | grep -q '^# linx plot "out\\140touch ' ||
  fail "plots.gp's first line: $(head -1 "$out/plots/plots.gp")"

if command -v povray >/dev/null; then
  "$linx" render "$out" --frame last --width 64 --height 48 --antialias off >render.txt 2>&1 ||
    fail "linx render: $(cat render.txt)"
  clean_output render.txt "linx render"
  no_canary "linx render"
  # The names are one comment line each, shown as a terminal would show them.
  grep -qxF '// body 0: up\nper\x1b[2J\x1b]0;title\x07' "$out/render/scene.inc" ||
    fail "scene.inc: $(grep '^// body 0' "$out/render/scene.inc")"
  grep -qxF "// body 1: low\\u202eer $(printf '\xc3\xa9\xe6\x97\xa5') #declare X=1; */ /* \\u0085 \\x7f" \
    "$out/render/scene.inc" || fail "scene.inc: $(grep '^// body 1' "$out/render/scene.inc")"
fi

"$linx" vtk "$out" >vtk.txt 2>&1 || fail "linx vtk: $(cat vtk.txt)"
clean_output vtk.txt "linx vtk"
no_canary "linx vtk"

# A run folder crafted by hand: its scene.json names a joint with a newline and a backquote
# command; linx plot shows it as `\n`, runs nothing.
cp -r "$out" crafted
python3 - "$canary" <<'PY' || fail "cannot craft the run folder"
import csv, json, sys
s = json.load(open("crafted/scene.json"))
old, new = s["joints"][0]["name"], f"crafted\n`touch {sys.argv[1]}6`\r\x1b[31m"
s["joints"][0]["name"] = new
json.dump(s, open("crafted/scene.json", "w"))
rows = list(csv.reader(open("crafted/joints.csv", newline="")))
for row in rows[1:]:
    if row[1] == old:
        row[1] = new
csv.writer(open("crafted/joints.csv", "w", newline=""), lineterminator="\n").writerows(rows)
PY
"$linx" plot crafted >crafted.txt 2>&1 || fail "linx plot (crafted): $(cat crafted.txt)"
no_canary "linx plot (crafted)"
python3 - crafted/plots/joint_errors.svg "$canary" <<'PY' || fail "crafted: the title is not shown"
import sys
import xml.etree.ElementTree as ET
want = f"crafted\\n`touch {sys.argv[2]}6`\\r\\x1b[31m (hinge)"
texts = ["".join(e.itertext()) for e in ET.parse(sys.argv[1]).iter() if e.tag.endswith("text")]
if want not in texts:
    sys.exit(f"{want!r} not among {texts}")
PY

# The crafted folder brings a povray.ini whose Include_Header would write a file: povray reads
# linx's own ini instead.
if command -v povray >/dev/null; then
  mkdir -p crafted/render
  printf 'Include_Header=evil.inc\n' >crafted/render/povray.ini
  printf '#fopen F "CANARY_INI" write\n#write (F, "x")\n#fclose F\n' >crafted/render/evil.inc
  "$linx" render crafted --frame last --width 64 --height 48 --antialias off >crafted_render.txt 2>&1 ||
    fail "linx render (crafted): $(cat crafted_render.txt)"
  no_canary "linx render (crafted povray.ini)"
fi

# Messages: a name with a terminal escape is shown, not acted on; a NUL in a path does not cut
# the message short.
python3 - <<'PY'
import json
json.dump({"bodies": [{"name": "b", "mass": 1, "shapes": [{"type": "sphere", "radius": 1}]}],
           "joints": [{"name": "j", "type": "ball", "body1": "no\u001b[2Jbody",
                       "anchor": [0, 0, 0]}]},
          open("escape.json", "w"))
json.dump({"bodies": [{"name": "b", "mass": 1,
                       "shapes": [{"type": "mesh", "file": "m\u0000x.obj"}]}]},
          open("nul.json", "w"))
PY
"$linx" check escape.json >escape.txt 2>&1
status=$?
[ $status = 2 ] || fail "escape.json: exit status $status: $(cat escape.txt)"
clean_output escape.txt "linx check escape.json"
grep -qF 'no\x1b[2Jbody' escape.txt || fail "escape.json: $(cat escape.txt)"
"$linx" check nul.json >nul.txt 2>&1
status=$?
[ $status = 2 ] || fail "nul.json: exit status $status: $(cat nul.txt)"
clean_output nul.txt "linx check nul.json"
grep -qF 'm\0x.obj' nul.txt || fail "nul.json: the message stops at the NUL: $(cat nul.txt)"
no_canary "the messages"
echo "hostile names: ok"
