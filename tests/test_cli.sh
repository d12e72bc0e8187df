#!/usr/bin/env bash
# Tests of the `linx` command line, one case per ctest test:
#   test_cli.sh LINX EXAMPLES_DIR VERSION CASE
# Checks exit statuses, the one-line error format "linx: FILE: FIELD: PROBLEM", the CSV headers,
# and that a rejected or failed run leaves no output behind.
set -u

linx=$1
examples=$2
version=$3
case_name=$4

work=$(mktemp -d "${TMPDIR:-/tmp}/linx_cli.XXXXXX")
trap 'rm -rf "$work"' EXIT
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

# The error is exactly one line and starts with the given text.
expect_error_line() {
  [ "$(wc -l <err.txt)" -eq 1 ] || fail "expected one line on stderr"
  case "$(cat err.txt)" in
    "$1"*) ;;
    *) fail "stderr does not start with '$1'" ;;
  esac
}

expect_no_output_dir() {
  [ ! -e "$1" ] || fail "$1 exists: $(ls -A "$1")"
}

# A valid one-body scene: a pendulum bob, used as the base of the bad ones.
cat >good.json <<'EOF'
{
  "duration": 0.01,
  "bodies": [{"name": "bob", "mass": 1, "position": [1, 0, 0],
              "shapes": [{"type": "sphere", "radius": 0.05}]}],
  "joints": [{"name": "pivot", "type": "hinge", "body1": "bob", "anchor": [0, 0, 0],
              "axis": [0, 1, 0]}]
}
EOF

case "$case_name" in
  version)
    expect 0 "$linx" --version
    [ "$(cat out.txt)" = "linx $version" ] || fail "--version printed '$(cat out.txt)'"
    ;;

  usage)
    expect 0 "$linx" --help
    grep -q "run" out.txt || fail "--help does not list the run command"
    expect 2 "$linx"
    expect_error_line "linx: "
    expect 2 "$linx" simulate good.json
    expect_error_line "linx: "
    expect 2 "$linx" run good.json
    expect_error_line "linx: --out is required"
    expect 2 "$linx" run good.json --out out --every two
    expect_error_line "linx: "
    expect 2 "$linx" run good.json --out out --bogus
    expect_error_line "linx: "
    expect_no_output_dir out
    ;;

  check_examples)
    for scene in "$examples"/*.json; do
      expect 0 "$linx" check "$scene"
      grep -q "^$scene: ok: .* bod.*, .* joint.*, timestep .* s, duration .* s (.* steps), solver " out.txt ||
        fail "unexpected summary for $scene"
    done
    expect 0 "$linx" check good.json
    [ "$(cat out.txt)" = "good.json: ok: 1 body, 1 joint, timestep 0.001 s, duration 0.01 s (10 steps), solver auto, integrator auto (tolerance 1e-10)" ] ||
      fail "unexpected summary"
    ;;

  run_pendulum)
    expect 0 "$linx" run "$examples/pendulum.json" --out out --duration 0.05
    [ -s err.txt ] && fail "stderr is not a terminal: no progress bar expected"
    [ "$(cat out.txt)" = "wrote 4 files to out (51 frames, 50 steps, t = $(awk -F, 'END {print $1}' out/world.csv) s)" ] ||
      fail "unexpected summary line"
    # shellcheck disable=SC2012  # plain file names
    [ "$(ls -A out | tr '\n' ' ')" = "bodies.csv joints.csv scene.json world.csv " ] || fail "unexpected files: $(ls -A out)"
    [ "$(head -n 1 out/bodies.csv)" = "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz" ] || fail "bodies.csv header"
    [ "$(head -n 1 out/joints.csv)" = "time,joint,coordinate,error,fx,fy,fz,tx,ty,tz,coordinate2,coordinate3,coordinate4,coordinate5,coordinate6" ] || fail "joints.csv header"
    [ "$(head -n 1 out/world.csv)" = "time,kinetic_energy,potential_energy,total_energy,max_joint_error,solver_iterations,residual" ] ||
      fail "world.csv header"
    for f in bodies joints world; do
      [ "$(wc -l <out/$f.csv)" -eq 52 ] || fail "$f.csv: expected a header and 51 frames"
    done
    [ "$(sed -n 2p out/bodies.csv)" = "0,bob,1,0,0,1,0,0,0,0,0,0,0,0,0" ] || fail "initial state row"
    [ "$(sed -n 2p out/joints.csv)" = "0,pivot,0,0,0,0,0,0,0,0,,,,," ] || fail "initial joint row"

    # --every 20 over 50 steps: t = 0, steps 20 and 40, and the last step.
    expect 0 "$linx" run good.json --out every --duration 0.05 --timestep 0.001 --every 20
    [ "$(wc -l <every/world.csv)" -eq 5 ] || fail "--every 20: expected 4 frames"
    grep -q "(4 frames, 50 steps," out.txt || fail "--every 20: summary"
    # --threads changes nothing in the results, to the bit.
    expect 0 "$linx" run good.json --out threads --duration 0.05 --timestep 0.001 --every 20 --threads 2
    cmp -s every/bodies.csv threads/bodies.csv || fail "--threads 2: bodies.csv differs"
    ;;

  run_contacts)
    # The ball of bouncing_ball.json lands after 0.45 s: contacts.csv lists the ground-ball points,
    # their normal from ground to ball and a positive impulse at the impact.
    expect 0 "$linx" run "$examples/bouncing_ball.json" --out out --duration 0.6 --contacts
    grep -q "^wrote 5 files to out " out.txt || fail "summary: expected 5 files"
    [ "$(head -n 1 out/contacts.csv)" = "time,body1,body2,x,y,z,nx,ny,nz,depth,normal_impulse" ] ||
      fail "contacts.csv header"
    awk -F, 'NR > 1 && $2 == "ground" && $3 == "ball" && $7 == 0 && $8 == 0 && $9 == 1 {n++}
             END {exit !(n > 0)}' out/contacts.csv || fail "no ground-ball contact with normal +z"
    awk -F, 'NR > 1 && $11 > 0 {hit = 1} END {exit !hit}' out/contacts.csv ||
      fail "no positive normal impulse"
    expect 0 "$linx" run "$examples/bouncing_ball.json" --out plain --duration 0.6
    [ -e plain/contacts.csv ] && fail "contacts.csv written without --contacts"
    ;;

  run_breaks)
    # The ball of breaking_bridge.json lands at 0.207 s and breaks four of the welds: each is
    # reported as it breaks and listed in breaks.csv. A run of a scene without breakable joints in
    # the same folder removes that breaks.csv.
    expect 0 "$linx" run "$examples/breaking_bridge.json" --out out --duration 0.3 --every 100
    grep -q "^t = 0.207 s: joint 'weld4' broke: torque above its break_torque of 400 N m " out.txt ||
      fail "no report of weld4 breaking"
    grep -q "^wrote 5 files to out " out.txt || fail "summary: expected 5 files"
    [ "$(head -n 1 out/breaks.csv)" = "time,step,joint,fx,fy,fz,tx,ty,tz" ] || fail "breaks.csv header"
    [ "$(awk -F, 'NR > 1 && $2 == 207 {printf "%s ", $3}' out/breaks.csv)" = "weld0 weld4 weld7 weld8 " ] ||
      fail "breaks.csv: expected welds 0, 4, 7 and 8 broken in step 207"
    expect 0 "$linx" run "$examples/pendulum.json" --out out --duration 0.01
    [ -e out/breaks.csv ] && fail "breaks.csv of the earlier run left behind"
    ;;

  run_urdf)
    # A URDF robot runs as it is: its root fixed, or free with --floating-base; what linx does not
    # use is named in one warning line; a broken file is refused with exit 2.
    expect 0 "$linx" check "$examples/robots/three_link_arm.urdf"
    grep -q "^$examples/robots/three_link_arm.urdf: ok: 4 bodies, 3 joints, " out.txt ||
      fail "unexpected summary for the URDF arm"
    grep -q "^linx: warning: .*three_link_arm.urdf: not used by linx, ignored: joint limit effort and velocity" err.txt ||
      fail "no warning naming the limits' effort and velocity"
    expect 0 "$linx" run "$examples/robots/three_link_arm.urdf" --out out --duration 0.5 --every 100
    [ "$(awk -F, '$1 == 0.5 && $2 == "pitch1" {print ($3 > 0.5)}' out/joints.csv)" = 1 ] ||
      fail "the arm did not fall about pitch1"
    expect 0 "$linx" run "$examples/robots/three_link_arm.urdf" --floating-base --out out --duration 0.5
    [ "$(awk -F, '$1 == 0.5 && $2 == "base" {print ($5 < -1.1)}' out/bodies.csv)" = 1 ] ||
      fail "the floating base did not fall"
    printf '<robot name="r"><link name="a">' >broken.urdf
    expect 2 "$linx" check broken.urdf
    expect_error_line "linx: broken.urdf: line "
    ;;

  convert)
    # A URDF robot written as a scene file that checks as the robot does; a folder is no output.
    expect 0 "$linx" convert "$examples/robots/three_link_arm.urdf" out.json
    grep -q "^wrote out.json (4 bodies, 3 joints)$" out.txt || fail "unexpected summary of convert"
    grep -q "^linx: warning: " err.txt || fail "the URDF's warning was not shown"
    ls out.json.tmp-* >/dev/null 2>&1 && fail "a temporary file was left behind"
    expect 0 "$linx" check out.json
    grep -q "^out.json: ok: 4 bodies, 3 joints, " out.txt || fail "the converted scene does not check"
    mkdir folder
    expect 2 "$linx" convert "$examples/robots/three_link_arm.urdf" folder
    expect_error_line "linx: folder: is a directory"
    ;;

  run_mjcf)
    # An MJCF model runs as it is; an unsupported construct is refused naming the element's line.
    expect 0 "$linx" check "$examples/robots/four_bar.xml"
    grep -q "^$examples/robots/four_bar.xml: ok: 4 bodies, 4 joints, timestep 0.001 s, " out.txt ||
      fail "unexpected summary for the MJCF four-bar"
    expect 0 "$linx" run "$examples/robots/four_bar.xml" --out out --duration 1 --every 100
    [ "$(awk -F, '$1 == 1 && $2 == "C" {print ($4 < 1e-9)}' out/joints.csv)" = 1 ] ||
      fail "the four-bar's loop opened"
    # Two joints in one body are a serial joint, whose axes must be independent.
    printf '<mujoco><worldbody>\n<body name="b"><joint/><joint/><geom size="1"/></body></worldbody></mujoco>' >two.xml
    expect 2 "$linx" check two.xml
    expect_error_line "linx: two.xml: joint 'b_joint0+b_joint1': axes[1]: adds no motion that the axes before it do not already allow"
    ;;

  bad_scenes)
    printf '{"bodies": [{"name": "bob", "mas": 1}]}' >unknown.json
    printf '{\n  "bodies": [\n    {"name": "bob",}\n  ]\n}\n' >syntax.json
    printf '{"bodies": [{"name": "bob", "mass": 1e999, "inertia": [1, 1, 1]}]}' >overflow.json
    sed 's/"body1": "bob"/"body1": "bobb"/' good.json >nobody.json
    sed 's/"axis": \[0, 1, 0\]/"axis": [0, 0, 0]/' good.json >zeroaxis.json
    sed 's/"duration": 0.01/"duration": 0.0001/' good.json >tooshort.json
    for spec in \
      "unknown.json|linx: unknown.json: bodies[0].mas: unknown field (did you mean 'mass'?)" \
      "syntax.json|linx: syntax.json: line 3, column 20: syntax error" \
      "overflow.json|linx: overflow.json: bodies[0].mass: " \
      "nobody.json|linx: nobody.json: joints[0].body1: unknown body 'bobb' (did you mean 'bob'?)" \
      "zeroaxis.json|linx: zeroaxis.json: joints[0].axis: must not be zero" \
      "tooshort.json|linx: tooshort.json: duration: 0.0001 s is shorter than half a timestep"; do
      scene=${spec%%|*}
      message=${spec#*|}
      expect 2 "$linx" run "$scene" --out "out_$scene"
      expect_error_line "$message"
      expect_no_output_dir "out_$scene"
      expect 2 "$linx" check "$scene"
      expect_error_line "$message"
    done
    ;;

  bad_flags)
    for flags in "--every 0" "--every -3" "--timestep -1" "--timestep=-1" "--timestep 0" \
      "--duration nan" "--duration inf" "--duration 0" "--duration 0.0001" "--threads -1" "--threads 2000"; do
      # shellcheck disable=SC2086
      expect 2 "$linx" run good.json --out out $flags
      expect_error_line "linx: --"
      expect_no_output_dir out
    done
    expect 2 "$linx" run good.json --out out --every 0
    [ "$(cat err.txt)" = "linx: --every: must be at least 1, got 0" ] || fail "--every message"
    # A run folder whose run files would include the scene itself.
    mkdir here && cp good.json here/scene.json
    expect 2 "$linx" run here/scene.json --out here
    expect_error_line "linx: --out: here: the run would replace its own input here/scene.json (a scene; scene.json is a run file); move it out of the folder, or choose another folder"
    [ "$(cat here/scene.json)" = "$(cat good.json)" ] || fail "the scene was changed"
    expect 2 "$linx" run good.json --out out --timestep=-1
    [ "$(cat err.txt)" = "linx: --timestep: must be a finite number > 0, got -1" ] || fail "--timestep message"
    expect 2 "$linx" run good.json --out out --threads -1
    [ "$(cat err.txt)" = "linx: --threads: must be an integer in [0, 1024], got -1" ] || fail "--threads message"
    echo "not a directory" >taken
    expect 2 "$linx" run good.json --out taken
    expect_error_line "linx: --out: taken: exists and is not a directory"
    expect 2 "$linx" run good.json --out taken/sub
    expect_error_line "linx: --out: taken/sub: taken is a file, not a folder"
    expect 2 "$linx" run good.json --out ""
    expect_error_line "linx: --out: must not be empty"
    # Misspelt flags and commands are named, with the closest one.
    expect 2 "$linx" run good.json --out out --durtion 1
    expect_error_line "linx: --durtion: not a flag of linx run; did you mean --duration? (see linx run --help)"
    expect 2 "$linx" run good.json --out out --every 1.5
    expect_error_line "linx: --every: '1.5' is not a value it takes (see linx run --help)"
    expect 2 "$linx" run good.json --out out extra
    expect_error_line "linx: 'extra': an argument linx run does not take (see linx run --help)"
    expect 2 "$linx" rn good.json
    expect_error_line "linx: 'rn': not a command of linx; did you mean run? (see linx --help)"
    ;;

  missing_file)
    expect 2 "$linx" run missing.json --out out
    expect_error_line "linx: missing.json: cannot open: No such file or directory"
    expect_no_output_dir out
    expect 2 "$linx" check missing.json
    expect_error_line "linx: missing.json: cannot open"
    mkdir adir
    expect 2 "$linx" check adir
    expect_error_line "linx: adir: is a directory"
    ;;

  non_finite)
    # A free body fast enough that it passes the extent bound (1e8 m, linx/bounds.hpp) at the
    # third step (under a speed bound lifted to let it get there).
    cat >runaway.json <<'EOF'
{
  "gravity": [0, 0, 0], "timestep": 0.5, "duration": 2, "faults": {"max_speed": 1e8},
  "bodies": [{"name": "runaway", "mass": 1, "inertia": [1, 1, 1],
              "linear_velocity": [8e7, 0, 0]}]
}
EOF
    expect 3 "$linx" run runaway.json --out out
    expect_error_line "linx: runaway.json: bodies[0] (runaway): position 1.2e+08 m from the origin is beyond 1e+08 m, where doubles are too coarse to resolve a contact within the slop, after step 3 (t = 1.5 s); output kept up to t = 1 s in out; the last good state (t = 0 s) is in out/checkpoints/step_000000000000000.lxc"
    # The frames before the fault are kept, whole: t = 0, 0.5 and 1.
    [ "$(cut -d, -f1 out/world.csv | tr '\n' ' ')" = "time 0 0.5 1 " ] ||
      fail "world.csv of the faulted run: $(cat out/world.csv)"
    # Resumed from its last good state, it meets the same fault at the same step.
    expect 3 "$linx" resume out
    grep -q "is beyond 1e+08 m, .* after step 3 (t = 1.5 s)" err.txt || fail "resume: another fault"

    # Under the default speed bound the same body is refused by the check: it would stop at once.
    sed 's/, "faults": {"max_speed": 1e8}//' runaway.json >fast.json
    expect 2 "$linx" check fast.json
    expect_error_line "linx: fast.json: bodies[0].linear_velocity: the body starts at 8e+07 m/s, above faults.max_speed (10000 m/s) (raise the bound to allow it)"

    # A body that gravity makes too fast stops at the step where it passes the bound; the check
    # refuses it, as the first step would stop on it.
    cat >bound.json <<'EOF'
{
  "gravity": [3e4, 0, 0], "timestep": 0.5, "duration": 2,
  "bodies": [{"name": "runaway", "mass": 1, "inertia": [1, 1, 1]}]
}
EOF
    expect 2 "$linx" check bound.json
    expect_error_line "linx: bound.json: the first step would stop: bodies[0] (runaway): speed 15000 m/s is above faults.max_speed (10000 m/s) after step 1 (t = 0.5 s)"
    expect 3 "$linx" run bound.json --out bound
    expect_error_line "linx: bound.json: bodies[0] (runaway): speed 15000 m/s is above faults.max_speed (10000 m/s) after step 1 (t = 0.5 s); output kept up to t = 0 s in bound; the last good state (t = 0 s) is in bound/checkpoints/step_000000000000000.lxc"
    # Resumed from there with --on-fault continue, it warns at each step and goes on to the end.
    expect 0 "$linx" resume bound --on-fault continue
    [ "$(grep -c "after step [1234] .*; going on (--on-fault continue)" err.txt)" -eq 4 ] ||
      fail "resume --on-fault continue: expected four warnings"
    # --on-fault continue: a warning per fault, and the run goes on.
    expect 0 "$linx" run bound.json --out bound --on-fault continue
    [ "$(grep -c "linx: warning: bound.json: bodies\\[0\\] (runaway): speed .* m/s is above faults.max_speed (10000 m/s) after step [1234] .*; going on (--on-fault continue)" err.txt)" -eq 4 ] ||
      fail "--on-fault continue: expected four warnings"
    # An energy too large for a double stops the run even then (gravity 1e308: the body's kinetic
    # energy after one step, (g h)^2 / 2, is infinite).
    sed 's/3e4, 0, 0/1e308, 0, 0/' bound.json >infinite.json
    expect 3 "$linx" run infinite.json --out infinite --on-fault continue
    grep -q "bodies\[0\] (runaway): energy is not finite (kinetic inf J" err.txt ||
      fail "--on-fault continue: no stop on an infinite energy"
    ;;

  interrupt)
    # SIGINT and SIGTERM stop a long run at the end of a step; what it recorded is kept, whole.
    for signal in INT TERM; do
      rm -rf out
      "$linx" run "$examples/hinge_chain.json" --out out --duration 1000 >out.txt 2>err.txt &
      pid=$!
      for _ in $(seq 100); do
        [ "$( { wc -l <out/world.csv; } 2>/dev/null || echo 0)" -gt 3 ] && break
        sleep 0.1
      done
      [ "$(wc -l <out/world.csv)" -gt 3 ] || fail "the run did not start"
      kill -$signal "$pid"
      wait "$pid"
      status=$?
      [ "$status" -eq 130 ] || fail "SIG$signal: the run exited with $status, expected 130"
      expect_error_line "linx: $examples/hinge_chain.json: interrupted at step "
      # Its last frame is the step it stopped at, and the folder reads back.
      stopped=$(sed -n 's/.*interrupted at step [0-9]* (t = \([^ ]*\) s).*/\1/p' err.txt)
      [ "$(tail -n 1 out/world.csv | cut -d, -f1)" = "$stopped" ] ||
        fail "SIG$signal: world.csv ends at $(tail -n 1 out/world.csv | cut -d, -f1), not $stopped"
      expect 0 "$linx" vtk out
    done

    # SIGKILL at any moment: the folder still reads back, to the frames written.
    for delay in 0.3 0.7 1.1; do
      rm -rf out
      "$linx" run "$examples/hinge_chain.json" --out out --duration 1000 >out.txt 2>err.txt &
      pid=$!
      sleep $delay
      kill -KILL "$pid"
      wait "$pid" 2>/dev/null
      [ -e out/scene.json ] || continue  # killed before its first frame was written
      expect 0 "$linx" vtk out
    done

    # A step that takes far longer than a second (a thousand hinges between the same two bodies,
    # on one axis but each at its own point, so not refused as repeats: one dense solve of 5000
    # rows) is not waited for.
    {
      echo '{"duration": 1, "bodies": ['
      echo '{"name": "a", "mass": 1, "inertia": [1, 1, 1], "position": [0, 0, 0]},'
      echo '{"name": "b", "mass": 1, "inertia": [1, 1, 1], "position": [1, 0, 0]}], "joints": ['
      for i in $(seq 1000); do
        [ "$i" -gt 1 ] && echo ','
        echo "{\"name\": \"h$i\", \"type\": \"hinge\", \"body1\": \"a\", \"body2\": \"b\", \"anchor\": [0.5, 0, $i], \"axis\": [0, 0, 1]}"
      done
      echo ']}'
    } >redundant.json
    rm -rf out
    "$linx" run redundant.json --out out >out.txt 2>err.txt &
    pid=$!
    for _ in $(seq 100); do
      [ -e out/scene.json ] && break
      sleep 0.1
    done
    sleep 0.5
    start=$(date +%s%N)
    kill -TERM "$pid"
    wait "$pid"
    status=$?
    elapsed_ms=$((($(date +%s%N) - start) / 1000000))
    [ "$status" -eq 130 ] || fail "the long step: exited with $status, expected 130"
    [ "$elapsed_ms" -lt 5000 ] || fail "the long step: took $elapsed_ms ms to stop"
    grep -q "interrupted inside step 1, still running 1 s after the signal; output kept up to t = 0 s in out" err.txt ||
      fail "the long step: unexpected message"
    expect 0 "$linx" vtk out
    ;;

  checkpoint)
    # A run killed (SIGKILL) part-way and resumed from its newest checkpoint writes the same files,
    # byte for byte, as the run that was never stopped; so does one stopped with SIGINT.
    args=(run "$examples/pyramid.json" --duration 20 --every 10 --contacts --checkpoint-every 1)
    expect 0 "$linx" "${args[@]}" --out full
    for signal in KILL INT; do
      rm -rf stopped
      "$linx" "${args[@]}" --out stopped >out.txt 2>err.txt &
      pid=$!
      for _ in $(seq 200); do
        [ "$( { wc -l <stopped/world.csv; } 2>/dev/null || echo 0)" -gt 60 ] && break
        sleep 0.02
      done
      kill -$signal "$pid"
      wait "$pid" 2>/dev/null
      [ -n "$(ls stopped/checkpoints)" ] || fail "SIG$signal: no checkpoint written"
      expect 0 "$linx" resume stopped
      grep -q "^linx: resuming $examples/pyramid.json at step " err.txt || fail "no resume line"
      for f in scene.json bodies.csv joints.csv world.csv contacts.csv; do
        cmp -s full/$f stopped/$f || fail "SIG$signal: $f differs from the run never stopped"
      done
    done
    # A checkpoint named by its file; a finished run has nothing to resume from its last one.
    newest=$(ls stopped/checkpoints/*.lxc | tail -n 1)
    expect 0 "$linx" resume "$newest"
    cmp -s full/bodies.csv stopped/bodies.csv || fail "resume FILE: bodies.csv differs"

    # Bad checkpoints are refused, naming the file and what is wrong.
    cp "$newest" flipped.lxc
    size=$(stat -c %s flipped.lxc)
    # Every bit of the middle byte turned (a fixed byte would leave the file whole wherever the
    # middle byte happens to hold it, as the scene's path in the payload moves it).
    middle=$(od -An -tu1 -j $((size / 2)) -N 1 flipped.lxc | tr -d ' ')
    printf "\\x$(printf %02x $((middle ^ 0xff)))" | dd of=flipped.lxc bs=1 seek=$((size / 2)) conv=notrunc status=none
    cmp -s "$newest" flipped.lxc && fail "the checkpoint was not damaged"
    expect 2 "$linx" resume flipped.lxc
    expect_error_line "linx: flipped.lxc: checksum: does not match: the file is damaged"
    head -c $((size / 2)) "$newest" >cut.lxc
    expect 2 "$linx" resume cut.lxc
    expect_error_line "linx: cut.lxc: length: the header says "
    echo "not a checkpoint" >text.lxc
    expect 2 "$linx" resume text.lxc
    expect_error_line "linx: text.lxc: format: not a linx checkpoint"
    expect 2 "$linx" resume missing.lxc
    expect_error_line "linx: missing.lxc: file: "
    mkdir nothing
    expect 2 "$linx" resume nothing
    expect_error_line "linx: nothing: no checkpoints in nothing/checkpoints (run with --checkpoint-every)"
    expect 2 "$linx" run "$examples/pyramid.json" --out x --checkpoint-every 0
    expect_error_line "linx: --checkpoint-every: must be a finite number > 0, got 0"
    ;;

  view_server)
    # linx view: a stalled client does not block others, a request for many ranges is refused,
    # and only the files there when it started are served: a file swapped for a link later is not.
    expect 0 "$linx" run "$examples/pendulum.json" --out run --duration 0.1
    cp run/bodies.csv bodies.orig
    echo "a secret" >secret.txt
    "$linx" view run --port 0 >view.txt 2>view_err.txt &
    pid=$!
    for _ in $(seq 100); do
      grep -q "http://127.0.0.1:" view.txt && break
      sleep 0.1
    done
    port=$(sed -n 's|.*http://127.0.0.1:\([0-9]*\)/.*|\1|p' view.txt)
    [ -n "$port" ] || { kill "$pid"; fail "linx view did not start"; }
    # Twenty connections that send nothing, then a real request: answered within the timeout.
    stalled=()
    for _ in $(seq 20); do
      exec {fd}<>"/dev/tcp/127.0.0.1/$port"
      stalled+=("$fd")
    done
    start=$(date +%s%N)
    curl -s -m 10 -o manifest.json "http://127.0.0.1:$port/run/manifest.json" ||
      { kill "$pid"; fail "a request behind stalled connections was not answered"; }
    elapsed_ms=$((($(date +%s%N) - start) / 1000000))
    for fd in "${stalled[@]}"; do exec {fd}>&-; done
    [ "$elapsed_ms" -lt 6000 ] || { kill "$pid"; fail "answered after $elapsed_ms ms"; }
    grep -q '"bodies.csv"' manifest.json || { kill "$pid"; fail "manifest: $(cat manifest.json)"; }
    # Four ranges are served; 800 are refused.
    code=$(curl -s -o /dev/null -w '%{http_code}' -H "Range: bytes=0-0,2-2,4-4,6-6" \
      "http://127.0.0.1:$port/run/bodies.csv")
    [ "$code" = "206" ] || { kill "$pid"; fail "four ranges: HTTP $code"; }
    many=$(seq 0 2 1598 | sed 's/.*/&-&/' | paste -sd, -)
    code=$(curl -s -o /dev/null -w '%{http_code}' -H "Range: bytes=$many" \
      "http://127.0.0.1:$port/run/bodies.csv")
    [ "$code" = "416" ] || { kill "$pid"; fail "800 ranges: HTTP $code"; }
    # bodies.csv swapped for a link to another file: the original is what is served.
    mv run/bodies.csv run/moved.csv
    ln -s ../secret.txt run/bodies.csv
    curl -s -o served.csv "http://127.0.0.1:$port/run/bodies.csv"
    kill -TERM "$pid"
    wait "$pid"
    cmp -s served.csv bodies.orig || fail "a file swapped for a link was served: $(head -c 80 served.csv)"
    ;;

  soak)
    # A short soak of a contact scene and a jointed one: memory reported, flat after warm-up (the
    # chain folds onto itself in new ways, with more contacts at once, for its first 10 s).
    expect 0 "$linx" soak "$examples/box_stack.json" "$examples/hinge_chain.json" --steps 30000 \
      --report-every 5000
    [ "$(grep -c "after warm-up (step 15000), at most .* (flat)$" out.txt)" -eq 2 ] ||
      fail "soak: expected two flat heaps"
    [ "$(grep -c "^     30000 " out.txt)" -eq 2 ] || fail "soak: no report at the last step"
    expect 2 "$linx" soak "$examples/pyramid.json" --steps 5
    expect_error_line "linx: --steps: must be at least 10, got 5"
    expect 2 "$linx" soak missing.json
    expect_error_line "linx: missing.json: cannot open: No such file or directory"
    ;;

  plot)
    # linx plot: four PNG pictures of the asked size and their SVGs, drawn from the run's numbers.
    expect 0 "$linx" run "$examples/double_pendulum.json" --out run --duration 0.5 --every 10
    expect 0 "$linx" plot run --width 640 --height 360
    [ "$(cat out.txt)" = "wrote 4 plots to run/plots (PNG and SVG): energy, joint_coordinates, joint_errors, solver" ] ||
      fail "unexpected summary"
    for p in energy joint_coordinates joint_errors solver; do
      # PNG signature, then the IHDR chunk's width and height (big-endian) at bytes 16-23.
      [ "$(head -c 8 run/plots/$p.png | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] ||
        fail "$p.png is not a PNG"
      [ "$(od -An -tu1 -j16 -N8 run/plots/$p.png | tr -s ' ' | sed 's/^ //')" = "0 0 2 128 0 0 1 104" ] ||
        fail "$p.png is not 640x360"
      [ "$(stat -c %s run/plots/$p.png)" -gt 10000 ] || fail "$p.png is nearly empty"
      grep -q "<svg" run/plots/$p.svg || fail "$p.svg is not an SVG"
      grep -q "<path" run/plots/$p.svg || fail "$p.svg draws no curve"
    done
    # The energy plot's data are world.csv's columns, one line per frame.
    awk '/^\$energy << EOD/ {on = 1; next} /^EOD/ {on = 0} on' run/plots/plots.gp >plotted.txt
    awk -F, 'NR > 1 {print $1, $2, $3, $4}' run/world.csv >recorded.txt
    [ "$(wc -l <plotted.txt)" -eq "$(wc -l <recorded.txt)" ] && [ "$(wc -l <plotted.txt)" -gt 5 ] ||
      fail "energy plot: expected one point per frame"
    awk 'NR == FNR {a[FNR] = $0; next} {split(a[FNR], x, " "); for (i = 1; i <= 4; i++)
         if (x[i] + 0 != $i + 0) exit 1}' recorded.txt plotted.txt || fail "energy plot: data differ from world.csv"
    [ -z "$(ls -A run/plots | grep '^\.')" ] || fail "temporary files left: $(ls -A run/plots)"
    # A run without joints whose solver residual is 0 throughout: nothing for a log scale, so the
    # solver plot is drawn on a linear scale (and said so in its title) instead of failing.
    expect 0 "$linx" run "$examples/bouncing_ball.json" --out ball --duration 0.2
    expect 0 "$linx" plot ball
    [ "$(cat out.txt)" = "wrote 2 plots to ball/plots (PNG and SVG): energy, solver" ] ||
      fail "unexpected summary for a run without joints"
    grep -q '^set title "Solver (last step of each frame; all zero, linear scale)"$' ball/plots/plots.gp ||
      fail "solver plot: expected a linear scale for an all-zero residual"
    for p in energy solver; do
      [ "$(stat -c %s ball/plots/$p.png)" -gt 10000 ] || fail "ball: $p.png is nearly empty"
    done
    [ -z "$(ls -A ball/plots | grep '^\.')" ] || fail "temporary files left: $(ls -A ball/plots)"
    # gnuplot missing from PATH, or failing: one line each, told apart, and no temporary file left
    # (the failure's message carries the end of gnuplot's output, so its log is not kept).
    mkdir nobin fakebin
    expect 1 env PATH="$work/nobin" "$linx" plot ball
    expect_error_line "linx: plot: gnuplot not found on PATH"
    printf '#!/bin/sh\necho "bad plot" >&2\nexit 3\n' >fakebin/gnuplot
    chmod +x fakebin/gnuplot
    expect 1 env PATH="$work/fakebin:$PATH" "$linx" plot ball
    expect_error_line "linx: gnuplot failed (exit status 3) on ball/plots/plots.gp: bad plot"
    [ -z "$(ls -A ball/plots | grep '^\.')" ] || fail "temporary files left: $(ls -A ball/plots)"
    # A joint name with a newline stays inside its title: it does not become gnuplot commands.
    cat >named.json <<'EOF'
{"gravity": [0, 0, -9.81], "timestep": 0.001, "duration": 0.05,
 "bodies": [{"name": "bob", "mass": 1, "position": [1, 0, 0],
             "shapes": [{"type": "sphere", "radius": 0.05}]}],
 "joints": [{"name": "pin\nprint \"injected\"", "type": "hinge", "body1": "bob", "body2": "world",
             "anchor": [0, 0, 0], "axis": [0, 1, 0]}]}
EOF
    expect 0 "$linx" run named.json --out named
    expect 0 "$linx" plot named
    grep -q '^print' named/plots/plots.gp && fail "a joint name's newline reached plots.gp"
    # Shown as io::visible shows it (the newline as \n), every byte outside a plain set octal.
    grep -qF 'title "pin\134nprint \042injected\042 (hinge)"' named/plots/plots.gp ||
      fail "the joint's title is not on one line"
    # A folder that is not a run: one line naming the file, exit status 2, no plots.
    mkdir empty
    expect 2 "$linx" plot empty
    expect_error_line "linx: empty/scene.json: file: cannot be read"
    [ ! -e empty/plots ] || fail "plots written for a bad folder"
    expect 2 "$linx" plot run --width 5
    expect_error_line "linx: --width: must be an integer in [100, 10000], got 5"
    ;;

  *)
    echo "unknown case $case_name" >&2
    exit 1
    ;;
esac
echo "ok: $case_name"
