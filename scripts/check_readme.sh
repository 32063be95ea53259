#!/usr/bin/env bash
# Runs every command of README.md as printed: each line of its ```sh blocks
# that starts with `vibroatlas ` (as target/release/vibroatlas) and each
# ```python block (with Debian's python3), in a scratch folder holding links
# to configs/ and scripts/ and an out/ folder. Prints one line per command and
# exits non-zero when any fails. Used by scripts/test.sh.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
ln -s "$root/configs" "$work/configs"
ln -s "$root/scripts" "$work/scripts"
mkdir -p "$work/out"
cd "$work"
vibroatlas() { "$root/target/release/vibroatlas" "$@"; }
failed=0
count=0
run() {
    count=$((count + 1))
    if eval "$1" >"$work/last.out" 2>&1; then
        echo "check_readme: ok    $1"
    else
        echo "check_readme: FAIL  $1"
        tail -n 5 "$work/last.out" | sed 's/^/    /'
        failed=$((failed + 1))
    fi
}
while IFS= read -r cmd; do
    run "$cmd"
done < <(awk '/^```sh/{f=1;next} /^```/{f=0} f' "$root/README.md" | grep '^vibroatlas ' | sed 's/  *#.*$//')
# The Python examples read out/small.h5, made as README says. A ```text
# block right after one (the next fenced block) is what it prints, compared
# exactly: a change that moves a number moves the page too.
awk -v dir="$work" '
    /^```python/ { n++; f = 1; next }
    /^```text/ && after { t = 1; after = 0; file = dir "/py" n ".expected"; printf "" > file; next }
    /^```/ { if (f) { printf "%c", 0; after = 1 } else if (!t) { after = 0 }; f = 0; t = 0; next }
    f { print }
    t { print > file }
' "$root/README.md" > "$work/python-blocks"
n=0
while IFS= read -r -d '' block; do
    n=$((n + 1))
    printf '%s' "$block" > "py$n.py"
    if [ -e "py$n.expected" ]; then
        run "/usr/bin/python3 py$n.py > py$n.out && diff -u py$n.expected py$n.out"
    else
        run "/usr/bin/python3 py$n.py"
    fi
done < "$work/python-blocks"
# The README stays a page one reads through (issue 65): at most 400 lines.
lines=$(wc -l < "$root/README.md")
run "[ $lines -le 400 ] # README.md has $lines lines"
echo "check_readme: $count commands, $failed failed"
[ "$failed" -eq 0 ]
