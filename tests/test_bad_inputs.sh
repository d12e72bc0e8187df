#!/usr/bin/env bash
# The corpus of bad inputs (tests/bad_inputs/, docs/reliability.md "Inputs"): every file in
# expected.tsv goes through `linx check` from inside the folder; its exit status and the last line
# it printed on stderr (the refusal, or a warning) must be the ones written there, the folder's
# absolute path written as $DIR. Usage: test_bad_inputs.sh LINX DIR [--update] (--update rewrites
# expected.tsv from what linx prints now, for a reviewer to read in the diff).
set -uo pipefail
linx=$(realpath "$1")
dir=$(realpath "$2")
update=${3:-}
table=$dir/expected.tsv
stderr=$(mktemp)
trap 'rm -f "$stderr" "$stderr.new"' EXIT

count=0
failures=0
while IFS= read -r line; do
  IFS=$'\t' read -r name status message <<<"$line"
  if [[ -z $name || $name == \#* ]]; then
    [[ $update == --update ]] && printf '%s\n' "$line" >>"$stderr.new"
    continue
  fi
  count=$((count + 1))
  (cd "$dir" && timeout 60 "$linx" check "$name" >/dev/null 2>"$stderr")
  actual_status=$?
  actual=$(grep -v '^$' "$stderr" | tail -n 1)
  if [[ $update == --update ]]; then
    printf '%s\t%s\t%s\n' "$name" "$actual_status" "${actual//$dir/\$DIR}" >>"$stderr.new"
    continue
  fi
  expected=${message//\$DIR/$dir}
  if [[ $actual_status != "$status" || $actual != "$expected" ]]; then
    failures=$((failures + 1))
    printf 'FAIL %s\n  expected (exit %s): %s\n  got      (exit %s): %s\n' "$name" "$status" \
      "$expected" "$actual_status" "$actual"
  fi
done <"$table"

if [[ $update == --update ]]; then
  mv "$stderr.new" "$table"
  echo "rewrote $table ($count inputs)"
  exit 0
fi
echo "$count bad inputs, $failures not refused as expected"
[[ $count -gt 0 && $failures -eq 0 ]]
