#!/usr/bin/env bash
# Tests of the run folder's ownership (docs/reliability.md, "Output that survives a kill" and
# "Checkpoints"), one case per ctest test:
#   test_run_folder.sh LINX EXAMPLES_DIR CASE
# A run removes only its own entries, by exact name; it refuses to replace its own inputs; resume
# goes on only with the folder's own run, within the bounds of its scene; a torn row left by a kill
# is cut by the next command that opens the folder, never while a run writes it.
set -u

linx=$1
examples=$2
case_name=$3

work=$(mktemp -d "${TMPDIR:-/tmp}/linx_run_folder.XXXXXX")
live_pid=""
trap '[ -n "$live_pid" ] && kill -KILL "$live_pid" 2>/dev/null; rm -rf "$work"' EXIT
cd "$work" || exit 1

fail() {
  echo "FAIL: $*" >&2
  echo "--- stdout:" >&2; cat out.txt >&2 2>/dev/null
  echo "--- stderr:" >&2; cat err.txt >&2 2>/dev/null
  exit 1
}

# expect STATUS CMD...: runs CMD with stdout in out.txt and stderr in err.txt.
expect() {
  local want=$1
  shift
  "$@" >out.txt 2>err.txt
  local got=$?
  [ "$got" -eq "$want" ] || fail "'$*' exited with $got, expected $want"
}

# stderr is exactly this one line.
expect_error() {
  [ "$(cat err.txt)" = "$1" ] || fail "stderr is not '$1'"
}

# The error is exactly one line and starts with the given text.
expect_error_line() {
  [ "$(wc -l <err.txt)" -eq 1 ] || fail "expected one line on stderr"
  case "$(cat err.txt)" in
    "$1"*) ;;
    *) fail "stderr does not start with '$1'" ;;
  esac
}

# A listing of every entry under DIR with the checksum of each file: equal listings, equal trees.
tree_of() {
  (cd "$1" && find . -mindepth 1 | LC_ALL=C sort | while read -r p; do
    if [ -L "$p" ]; then echo "$p -> $(readlink "$p")"
    elif [ -f "$p" ]; then echo "$p $(sha256sum <"$p" | cut -c1-16)"
    else echo "$p/"; fi
  done)
}

cat >good.json <<'EOF2'
{
  "duration": 1,
  "bodies": [{"name": "bob", "mass": 1, "position": [1, 0, 0],
              "shapes": [{"type": "sphere", "radius": 0.05}]}],
  "joints": [{"name": "pivot", "type": "hinge", "body1": "bob", "anchor": [0, 0, 0],
              "axis": [0, 1, 0]}]
}
EOF2
# Another run's scene: two bodies.
cat >other.json <<'EOF2'
{
  "duration": 1,
  "bodies": [{"name": "a", "mass": 1, "position": [1, 0, 0],
              "shapes": [{"type": "sphere", "radius": 0.05}]},
             {"name": "b", "mass": 1, "position": [2, 0, 0],
              "shapes": [{"type": "sphere", "radius": 0.05}]}],
  "joints": [{"name": "pivot", "type": "hinge", "body1": "a", "anchor": [0, 0, 0],
              "axis": [0, 1, 0]},
             {"name": "link", "type": "hinge", "body1": "a", "body2": "b", "anchor": [1, 0, 0],
              "axis": [0, 1, 0]}]
}
EOF2

case "$case_name" in
  user_files)
    # The user's own folders named like the run's, and files in them: all kept, byte for byte.
    mkdir -p proj/plots proj/render proj/vtk/sub proj/checkpoints proj/plots/energy.png
    echo "my notes" >proj/plots/notes.txt
    echo "todo" >proj/render/todo.txt
    echo "my frame notes" >proj/render/frame_notes.txt  # not a frame: render keeps it too
    echo "mine" >proj/vtk/mine.vtp
    echo "deep" >proj/vtk/sub/bodies_000001.vtp
    echo "backup" >proj/checkpoints/step_1.lxc.bak
    echo "mine" >proj/checkpoints/step_-1.lxc  # not a step number: never pruned as the oldest checkpoint
    echo "notes" >proj/notes.txt
    echo "picture" >proj/plots/energy.png/inside.txt  # a folder where linx writes a file
    tree_of proj >before.txt
    expect 0 "$linx" run good.json --out proj
    tree_of proj | grep -v -e '^./scene.json ' -e '^./bodies.csv ' -e '^./joints.csv ' \
      -e '^./world.csv ' >after.txt
    diff before.txt after.txt >diff.txt || fail "the user's files changed: $(cat diff.txt)"

    # Every file the tools write is the run's own: a second run leaves only the user's files.
    rm -rf proj/plots/energy.png
    expect 0 "$linx" run good.json --out proj --checkpoint-every 0.25 --vtk
    expect 0 "$linx" plot proj
    expect 0 "$linx" render proj --width 64 --height 48 --fps 4 --video gif
    expect 0 "$linx" render proj --width 64 --height 48 --frame last
    [ -f proj/render.gif ] && [ -n "$(ls proj/render/still_*.png)" ] || fail "no video or still"
    [ -n "$(ls proj/checkpoints/step_*.lxc)" ] || fail "no checkpoint written"
    # What a killed tool leaves: the temporary files of the writes, and their logs.
    touch proj/.scene.json.tmp proj/run.pvd.tmp proj/.render.part.mp4 proj/render/.frame_000001.pov.tmp \
      proj/render/frame_000001.part.png proj/plots/.energy.png.tmp proj/vtk/bodies_000001.vtp.tmp \
      proj/checkpoints/.step_000000000000010.lxc.tmp
    expect 0 "$linx" run good.json --out proj
    tree_of proj | grep -v -e '^./scene.json ' -e '^./bodies.csv ' -e '^./joints.csv ' \
      -e '^./world.csv ' >after.txt
    grep -v '^./plots/energy.png' before.txt >expected.txt
    diff expected.txt after.txt >diff.txt || fail "the tools' files were not all removed, or the user's changed: $(cat diff.txt)"

    # The run folders linx made itself, with nothing of the user's in them, are removed.
    expect 0 "$linx" run good.json --out clean --vtk --checkpoint-every 0.25
    expect 0 "$linx" plot clean
    expect 0 "$linx" run good.json --out clean
    [ "$(ls -A clean | tr '\n' ' ')" = "bodies.csv joints.csv scene.json world.csv " ] ||
      fail "clean holds $(ls -A clean)"

    # A link in place of a run folder is removed as a link; what it points to is kept.
    mkdir -p elsewhere && echo "keep" >elsewhere/energy.png
    ln -s ../elsewhere linked_plots && mkdir linked && mv linked_plots linked/plots
    expect 0 "$linx" run good.json --out linked
    [ ! -e linked/plots ] && [ "$(cat elsewhere/energy.png)" = "keep" ] || fail "the link was followed"

    # A folder of the user's where the run writes one of its files: refused, nothing removed.
    mkdir -p taken/world.csv && cp proj/scene.json taken/scene.json && echo "x" >taken/world.csv/a
    tree_of taken >before.txt
    expect 2 "$linx" run good.json --out taken
    expect_error "linx: --out: taken/world.csv: a folder where the run writes its file world.csv: linx leaves it alone; move it, or choose another folder"
    tree_of taken >after.txt
    diff before.txt after.txt >/dev/null || fail "the refused run changed taken/"
    ;;

  own_inputs)
    # A scene that reads a table named like a run file in its own output folder.
    mkdir proj
    printf 'time,force\n0,0\n1,2\n' >proj/world.csv
    sed 's/"axis": \[0, 1, 0\]}/"axis": [0, 1, 0], "force": {"file": "world.csv"}}/' good.json >proj/table.json
    grep -q '"file": "world.csv"' proj/table.json || fail "the scene has no table"
    tree_of proj >before.txt
    expect 2 "$linx" run proj/table.json --out proj
    expect_error "linx: --out: proj: the run would replace its own input proj/world.csv (a table; world.csv is a run file); move it out of the folder, or choose another folder"
    tree_of proj >after.txt
    diff before.txt after.txt >/dev/null || fail "the refused run changed proj/"
    # The same through links: the table a link to the folder's world.csv, or world.csv a link to
    # the table.
    mkdir data && ln -s ../proj/world.csv data/t.csv
    sed 's/"world.csv"/"data\/t.csv"/' proj/table.json >via_link.json
    expect 2 "$linx" run via_link.json --out proj
    expect_error "linx: --out: proj: the run would replace its own input data/t.csv (a table; world.csv is a run file); move it out of the folder, or choose another folder"
    # world.csv a link to the table: the link is removed as a link, the table kept.
    mkdir proj2 && printf 'time,force\n0,0\n1,2\n' >data/table.csv && ln -s ../data/table.csv proj2/world.csv
    sed 's/"world.csv"/"data\/table.csv"/' proj/table.json >linked_out.json
    expect 0 "$linx" run linked_out.json --out proj2
    [ ! -L proj2/world.csv ] && [ "$(cat data/table.csv)" = "$(printf 'time,force\n0,0\n1,2')" ] ||
      fail "the link was followed"
    # The scene itself as scene.json.
    mkdir here && cp good.json here/scene.json
    expect 2 "$linx" run here/scene.json --out here
    expect_error "linx: --out: here: the run would replace its own input here/scene.json (a scene; scene.json is a run file); move it out of the folder, or choose another folder"
    cmp -s good.json here/scene.json || fail "the scene was changed"
    # A table among the checkpoints' names.
    mkdir -p deep/checkpoints && printf 'time,force\n0,0\n1,2\n' >deep/checkpoints/step_7.lxc
    sed 's/"world.csv"/"checkpoints\/step_7.lxc"/' proj/table.json >deep/scene_deep.json
    expect 2 "$linx" run deep/scene_deep.json --out deep
    expect_error "linx: --out: deep: the run would replace its own input deep/checkpoints/step_7.lxc (a table; checkpoints/step_7.lxc is a run file); move it out of the folder, or choose another folder"
    # A table of the user's elsewhere in the folder (not a run file's name) is read and kept.
    mkdir -p kept/plots && printf 'time,force\n0,0\n1,2\n' >kept/plots/input.csv
    sed 's/"world.csv"/"kept\/plots\/input.csv"/' proj/table.json >kept.json
    expect 0 "$linx" run kept.json --out kept
    [ "$(cat kept/plots/input.csv)" = "$(printf 'time,force\n0,0\n1,2')" ] || fail "input.csv changed"
    ;;

  resume_identity)
    # A run and its checkpoints; and another scene's run.
    expect 0 "$linx" run good.json --out a --checkpoint-every 0.5
    cp -r a full
    expect 0 "$linx" run other.json --out b --checkpoint-every 0.5
    own=$(ls a/checkpoints/*.lxc | tail -n 1)
    theirs=$(ls b/checkpoints/*.lxc | tail -n 1)
    name=$(basename "$own")
    # Resumed from its own checkpoint: the files of the run never stopped.
    expect 0 "$linx" resume a
    for f in scene.json bodies.csv joints.csv world.csv; do cmp -s full/$f a/$f || fail "$f differs"; done

    refused() {  # refused DIR: resume exits 2 and DIR is as it was
      tree_of "$1" >before.txt
      expect 2 "$linx" resume "$1"
      tree_of "$1" >after.txt
      diff before.txt after.txt >/dev/null || fail "the refused resume changed $1"
    }
    # Another run's checkpoint copied in, or linked to.
    cp -r full c1 && cp "$theirs" c1/checkpoints/step_999999999999999.lxc
    refused c1
    expect_error_line "linx: c1/checkpoints/step_999999999999999.lxc: run folder: c1/scene.json is not the scene.json of the checkpoint's run ("
    cp -r full c2 && ln -s "$work/$theirs" c2/checkpoints/step_999999999999999.lxc
    refused c2
    expect_error "linx: c2/checkpoints/step_999999999999999.lxc: file: a link to $(realpath "$theirs"), outside the run folder c2: another run's checkpoint; resume that run's own folder"
    cp -r full c3 && ln -s "$work/b/checkpoints" c3/checkpoints.tmp && rm -rf c3/checkpoints && mv c3/checkpoints.tmp c3/checkpoints
    refused c3
    expect_error_line "linx: c3/checkpoints/"
    grep -q "outside the run folder c3" err.txt || fail "a linked checkpoints folder was not refused"
    # scene.json deleted.
    cp -r full c4 && rm c4/scene.json
    refused c4
    expect_error "linx: c4/checkpoints/$name: run folder: c4/scene.json: cannot open: No such file or directory: the folder holds no run to go on with"
    # A CSV file shorter than the checkpoint recorded, missing, or of another header.
    cp -r full c5 && head -n 3 full/world.csv >c5/world.csv
    refused c5
    expect_error_line "linx: c5/checkpoints/$name: run folder: c5/world.csv: $(stat -c %s c5/world.csv) bytes, shorter than the "
    cp -r full c6 && rm c6/joints.csv
    refused c6
    expect_error "linx: c6/checkpoints/$name: run folder: c6/joints.csv: missing"
    cp -r full c7 && sed -i '1s/kinetic_energy/kinetic_energZ/' c7/world.csv
    refused c7
    expect_error "linx: c7/checkpoints/$name: run folder: c7/world.csv: its first line is not the header 'time,kinetic_energy,potential_energy,total_energy,max_joint_error,solver_iterations,residual' (not this run's file?)"
    # Another run's checkpoint forged, with a valid checksum, to name this folder's scene.json:
    # its world's bodies and joints are not the folder's.
    forge_identity() {  # forge_identity CHECKPOINT SCENE_JSON BODIES JOINTS OUT
      python3 - "$@" <<'PY'
import struct, sys, zlib
src, scene, bodies, joints, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
data = open(src, "rb").read()
payload = bytearray(data[24:-4])
text = open(scene, "rb").read()
struct.pack_into("<QIqq", payload, len(payload) - 28, len(text), zlib.crc32(text), bodies, joints)
open(out, "wb").write(data[:24] + bytes(payload) + struct.pack("<I", zlib.crc32(payload)))
PY
    }
    cp -r full c9 && forge_identity "$theirs" full/scene.json 1 1 c9/checkpoints/step_999999999999999.lxc
    refused c9
    expect_error "linx: c9/checkpoints/step_999999999999999.lxc: scene: 2 bodies and 2 joints; its run recorded 1 and 1"
    cp -r full c10 && forge_identity "$theirs" full/scene.json 2 2 c10/checkpoints/step_999999999999999.lxc
    refused c10
    expect_error "linx: c10/checkpoints/step_999999999999999.lxc: scene: its bodies are not those of c10/scene.json"
    # Another run's files under this run's scene.json: the counts and the bodies differ.
    cp -r b c8 && cp full/scene.json c8/scene.json
    refused c8
    expect_error_line "linx: c8/checkpoints/"
    ;;

  resume_bounds)
    # A forged checkpoint with a valid checksum: its step count 2^62, its frames or its time
    # beyond its scene's run. Refused at once, naming the bound.
    expect 0 "$linx" run good.json --out a --checkpoint-every 0.5
    own=$(ls a/checkpoints/*.lxc | tail -n 1)
    forge() {  # forge FIELD VALUE OUT: rewrites a field of the payload and its CRC-32
      python3 - "$own" "$1" "$2" "$3" <<'PY'
import struct, sys, zlib
src, field, value, out = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
data = open(src, "rb").read()
payload = bytearray(data[24:-4])
at = 0
for _ in range(2):  # scene, source: u64 length and the bytes
    (n,) = struct.unpack_from("<Q", payload, at)
    at += 8 + n
layout = {"steps": (at, "<q"), "every": (at + 8, "<i"), "frames": (at + 8 + 4 + 8 + 3, "<q")}
offset, fmt = layout[field]
struct.pack_into(fmt, payload, offset, value)
open(out, "wb").write(data[:24] + bytes(payload) + struct.pack("<I", zlib.crc32(payload)))
PY
    }
    cp -r a f1 && forge steps $((1 << 62)) "f1/checkpoints/$(basename "$own")"
    start=$(date +%s)
    timeout 20 "$linx" resume f1 >out.txt 2>err.txt
    status=$?
    [ "$status" -eq 2 ] || fail "resume of 2^62 steps exited with $status"
    expect_error "linx: f1/checkpoints/$(basename "$own"): steps: 4611686018427387904 steps, more than its scene's duration / timestep + 1 (1 s / 0.001 s + 1 = 1001)"
    [ $(( $(date +%s) - start )) -lt 10 ] || fail "the refusal took long"
    cp -r a f2 && forge frames 100000 "f2/checkpoints/$(basename "$own")"
    expect 2 "$linx" resume f2
    expect_error "linx: f2/checkpoints/$(basename "$own"): frames: 100000 frames at step 500: more than one per step and the first"
    # A checkpoint of format version 1 (before checkpoints recorded their run folder).
    cp -r a f3 && printf '\x01' | dd of="f3/checkpoints/$(basename "$own")" bs=1 seek=8 conv=notrunc status=none
    expect 2 "$linx" resume f3
    expect_error "linx: f3/checkpoints/$(basename "$own"): version: format version 1 (an older linx's, which did not record its run folder: rerun the scene); this linx reads version 2"
    # The unforged checkpoint still resumes.
    expect 0 "$linx" resume a
    ;;

  torn_row)
    expect 0 "$linx" run good.json --out out --duration 0.01
    cp -r out whole
    # A row torn by a kill (5 fields under a header of 15), and a frame only bodies.csv has.
    printf '0.011,bob,1,2,3' >>out/bodies.csv
    expect 0 "$linx" vtk out
    grep -q "^linx: note: out/bodies.csv: cut 15 bytes after its last whole frame" err.txt || fail "no note"
    cmp -s whole/bodies.csv out/bodies.csv || fail "bodies.csv was not cut to its last whole frame"
    tail -n 1 whole/bodies.csv | sed 's/^0.01,/0.011,/' >>out/bodies.csv
    printf '0.011,pivot' >>out/joints.csv
    expect 0 "$linx" plot out
    for f in bodies.csv joints.csv world.csv; do cmp -s whole/$f out/$f || fail "$f not cut"; done
    expect 0 "$linx" plot out
    [ ! -s err.txt ] || fail "a whole folder was cut again"
    # A run killed with SIGKILL: the next command leaves every file whole rows of whole frames.
    "$linx" run "$examples/pyramid.json" --duration 20 --out killed >/dev/null 2>&1 &
    live_pid=$!
    for _ in $(seq 300); do
      [ "$( { wc -l <killed/world.csv; } 2>/dev/null || echo 0)" -gt 30 ] && break
      sleep 0.02
    done
    kill -KILL "$live_pid"; wait "$live_pid" 2>/dev/null; live_pid=""
    expect 0 "$linx" vtk killed
    frames=$(($(wc -l <killed/world.csv) - 1))
    [ -n "$(tail -c 1 killed/bodies.csv | tr -d '\n')" ] && fail "bodies.csv ends part-way"
    awk -F, 'NF != 15 { exit 1 }' killed/bodies.csv || fail "bodies.csv has a row of other than 15 fields"
    awk -F, 'NF != 7 { exit 1 }' killed/world.csv || fail "world.csv has a row of other than 7 fields"
    [ $(($(wc -l <killed/bodies.csv) - 1)) -gt 0 ] || fail "no frames"
    [ $(( ($(wc -l <killed/bodies.csv) - 1) % frames )) -eq 0 ] || fail "bodies.csv is not $frames whole frames"
    ;;

  lock)
    # A folder a run is writing: another run into it is refused, and so is a resume.
    "$linx" run "$examples/pyramid.json" --duration 60 --out live --checkpoint-every 0.1 >/dev/null 2>&1 &
    live_pid=$!
    for _ in $(seq 500); do
      [ -n "$(ls live/checkpoints 2>/dev/null)" ] && [ "$(wc -l <live/world.csv)" -gt 5 ] && break
      sleep 0.02
    done
    kill -0 "$live_pid" 2>/dev/null || fail "the live run ended early"
    expect 2 "$linx" run good.json --out live
    expect_error "linx: --out: live: another run or recording is writing into this folder (it holds the folder's lock); wait for it to end, or choose another folder"
    [ -f live/checkpoints/"$(ls live/checkpoints | tail -n 1)" ] || fail "the live run's files were removed"
    expect 2 "$linx" resume live
    expect_error_line "linx: live/checkpoints/"
    grep -q "another run or recording is writing into this folder" err.txt || fail "resume was not refused"
    # (That a command reading the live folder does not cut it is test_run_folder's
    # OpenRunCutsATornRowOnlyWhenNoRecorderHoldsTheFolder: here the files grow while read.)
    kill -INT "$live_pid"; wait "$live_pid"; live_pid=""
    # Once it has stopped, the folder is free.
    expect 0 "$linx" run good.json --out live --duration 0.01
    ;;

  *)
    echo "unknown case $case_name" >&2
    exit 2
    ;;
esac
exit 0
