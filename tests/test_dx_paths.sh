#!/usr/bin/env bash
# Host-side check that scripts/dx runs a command with the caller's paths (issue 20).
# Run on the host (`make test-dx-paths`, part of `make test`), not by pytest: pytest
# itself runs inside the environment, where it cannot see what landed on the host.
#
# From a fresh folder in /tmp (outside the clone), one `scripts/dx python3` call
#   - checks that its working directory and $HOME are the caller's,
#   - writes through a relative path, into a new folder under /tmp and into $HOME,
#   - reads an existing file and creates a folder (whose parent exists), both given
#     as absolute arguments in a folder outside /tmp, $HOME and the clone
#     (next to the clone, else under /), once as --out=PATH,
# then this script checks on the host that every file is there with its content.
set -euo pipefail

PROJECT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)
DX=$PROJECT/scripts/dx
tag=dx-paths.$$.$RANDOM
made=()
cleanup() { [ ${#made[@]} -eq 0 ] || rm -rf -- "${made[@]}"; }
trap cleanup EXIT

ok() { echo "[dx-paths] ok: $*"; }
fail() { echo "[dx-paths] FAILED: $*" >&2; exit 1; }

under() {  # is $1 at or below one of the folders $2...?
  local p=$1 d
  shift
  for d in "$@"; do
    [ -n "$d" ] || continue
    case "$p" in "$d" | "$d"/*) return 0 ;; esac
  done
  return 1
}

work=$(mktemp -d "/tmp/$tag.cwd.XXXXXX")
made+=("$work")
tmp_new=/tmp/$tag.new  # does not exist yet
made+=("$tmp_new")
home_dir=
if [ -n "${HOME:-}" ] && [ -d "$HOME" ] && [ -w "$HOME" ]; then
  home_dir=$(mktemp -d "$HOME/.$tag.XXXXXX")
  made+=("$home_dir")
fi

# A folder outside /tmp, /var/tmp, $HOME and the clone: the arguments' own binds.
home_phys=
if [ -n "${HOME:-}" ] && [ -d "$HOME" ]; then home_phys=$(cd "$HOME" && pwd -P); fi
elsewhere=
for parent in "$(dirname "$PROJECT")" /; do
  parent=$(cd "$parent" && pwd -P)
  under "${parent%/}/x" /tmp /var/tmp "$home_phys" "$PROJECT" && continue
  [ -w "$parent" ] || continue
  elsewhere=$(mktemp -d "${parent%/}/.$tag.XXXXXX") || continue
  made+=("$elsewhere")
  break
done

cd "$work"
args=("$work" "${HOME:-}" "$tmp_new/a/b" "${home_dir:-}")
if [ -n "$elsewhere" ]; then
  mkdir "$elsewhere/in"
  echo "scene from elsewhere" >"$elsewhere/in/scene.txt"
  args+=("$elsewhere/in/scene.txt" "--out=$elsewhere/new")
fi

DX_QUIET=1 "$DX" python3 - "${args[@]}" <<'PY' || fail "scripts/dx python3 exited $?"
import os
import sys

cwd, home, tmp_new, home_dir, *rest = sys.argv[1:]
assert os.getcwd() == cwd, f"working directory inside: {os.getcwd()}, outside: {cwd}"
assert os.environ.get("HOME", "") == home, f"HOME inside: {os.environ.get('HOME')}, outside: {home}"
os.makedirs("rel/sub")
with open("rel/sub/out.txt", "w") as f:
    f.write("relative\n")
os.makedirs(tmp_new)
with open(os.path.join(tmp_new, "out.txt"), "w") as f:
    f.write("tmp\n")
if home_dir:
    with open(os.path.join(home_dir, "out.txt"), "w") as f:
        f.write("home\n")
if rest:
    scene, out = rest[0], rest[1].split("=", 1)[1]
    with open(scene) as f:
        text = f.read()
    os.makedirs(out)
    with open(os.path.join(out, "copy.txt"), "w") as f:
        f.write(text)
PY

ok "working directory and HOME are the caller's ($work, ${HOME:-unset})"
check() {  # file, expected content, what
  [ -f "$1" ] || fail "$3: $1 is not on the host"
  [ "$(cat "$1")" = "$2" ] || fail "$3: $1 holds '$(cat "$1")', not '$2'"
  ok "$3: $1"
}
check "$work/rel/sub/out.txt" relative "relative path from a folder outside the clone"
check "$tmp_new/a/b/out.txt" tmp "new folder under /tmp"
if [ -n "$home_dir" ]; then
  check "$home_dir/out.txt" home "file in \$HOME"
else
  echo "[dx-paths] skipped: \$HOME is not a writable folder"
fi
if [ -n "$elsewhere" ]; then
  check "$elsewhere/new/copy.txt" "scene from elsewhere" \
    "existing file and new folder (--out=) outside /tmp, \$HOME and the clone"
else
  echo "[dx-paths] skipped: no writable folder outside /tmp, \$HOME and the clone"
fi
echo "[dx-paths] all checks done"
