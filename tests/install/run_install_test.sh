#!/usr/bin/env bash
# run_install_test.sh PART BUILD_DIR SOURCE_DIR: the installed engine works on its own, wherever its
# tree is moved. `cmake --install BUILD_DIR --prefix P` into a temporary folder; the tree is then
# moved elsewhere, and from an unrelated folder, with ROGER_HOME unset, PART checks:
#   moved   roger check on a shipped scenario (by path, and by a bare name found in the moved tree
#           only); roger eval of a shipped curriculum named bare (its Lua libraries found through
#           require); roger run <moved>/share/roger/scripts/quick.lua --out DIR must leave a
#           complete results folder whose tables and CSVs equal tests/golden/quick, which a copy
#           of the install resumes; a copy of quick.lua checks in a folder of one's own.
#   hidden  the same with the source and build trees hidden under empty folders (a mount namespace:
#           root and unshare of util-linux), so that nothing can be read from them.
#   deb     `cpack -G DEB` builds the Debian package, which must hold the same files under /usr and
#           declare what it needs; unpacked (dpkg-deb -x) into a folder, its roger works too.
#
# Exit status: 0 passed, 1 failed, 77 skipped: hidden without root or mount namespaces, deb without
# cpack or dpkg-deb (dpkg-dev). Under CI (CI=true), which installs them and runs as root, a skip is
# a failure (tests/tools/skip.sh).
set -euo pipefail

if [ $# -ne 3 ] || [[ ! "$1" =~ ^(moved|hidden|deb)$ ]]; then
  echo "usage: $0 moved|hidden|deb BUILD_DIR SOURCE_DIR" >&2
  exit 1
fi
part=$1 build=$(readlink -f "$2") source=$(readlink -f "$3")
# shellcheck source=tests/tools/skip.sh
. "$source/tests/tools/skip.sh"  # skip: exit 77, or a failure under CI=true
fail() { echo "FAILED ($part): $*"; exit 1; }
case $part in
  hidden)
    [ "$(id -u)" = 0 ] || skip "hiding the sources needs root (a mount namespace)"
    unshare --mount --propagation private true 2>/dev/null ||
      skip "no mount namespaces here (unshare of util-linux, CAP_SYS_ADMIN)" ;;
  deb)
    command -v cpack >/dev/null && command -v dpkg-deb >/dev/null ||
      skip "no cpack or dpkg-deb (apt-get install cmake dpkg-dev, as .ci/install does)" ;;
esac
work=$(mktemp -d /tmp/roger_install_XXXXXX)
trap 'rm -rf "$work"' EXIT
unset ROGER_HOME

cmake --install "$build" --prefix "$work/prefix" >"$work/install.log" 2>&1 ||
  { cat "$work/install.log"; fail "cmake --install"; }
for f in bin/roger share/roger/scenarios/cluttered.lua share/roger/scenarios/lib share/roger/curricula/lib/skills.lua \
         share/roger/scripts/quick.lua share/roger/scripts/slurm/submit.sh share/roger/web/episode.html \
         share/roger/docs/api/scenario.lua share/roger/.luarc.json share/roger/.luacheckrc \
         share/doc/roger/README.md; do
  [ -e "$work/prefix/$f" ] || fail "the install has no $f"
done
# A copy of the installed package outside its prefix (a venv's, or one installed there with
# -DROGER_PYTHON_INSTALL_DIR) reads the data cmake --install recorded beside it, not the source tree
# (found by a probe): a curriculum only the prefix has is found by its bare name.
installed_module=$(find "$work/prefix/lib" -name '_roger*.so' 2>/dev/null | head -1)
if [ "$part" = moved ] && [ -n "$installed_module" ]; then
  mkdir -p "$work/venv"
  cp -r "$(dirname "$installed_module")" "$work/venv/"
  cp "$work/prefix/share/roger/curricula/paper.lua" "$work/prefix/share/roger/curricula/only_prefix_paper.lua"
  (cd "$work" && PYTHONPATH=$work/venv /usr/bin/python3 -c "
import roger
roger.make('only_prefix_paper', 'SG', 'B1').reset(seed=1)
") >"$work/venv.log" 2>&1 || { cat "$work/venv.log"; fail "a copy of the installed package outside the prefix"; }
  rm -rf "$work/venv" "$work/prefix/share/roger/curricula/only_prefix_paper.lua"
fi
mv "$work/prefix" "$work/moved"
tree=$work/moved
# A scenario only the moved tree has: found by its bare name, it proves where roger looks.
cp "$tree/share/roger/scenarios/unobstructed.lua" "$tree/share/roger/scenarios/only_installed.lua"
cp "$source/tests/tools/compare_results.sh" "$work/"
cp -r "$source/tests/golden/quick" "$work/golden"
mkdir -p "$work/elsewhere"

# The checks, run from the unrelated folder: a function so that it can run hidden from the sources.
checks() {
  set -euo pipefail
  cd "$work/elsewhere"
  local roger=$tree/bin/roger
  "$roger" check "$tree/share/roger/scenarios/cluttered.lua" || { echo "roger check of a shipped scenario"; return 1; }
  "$roger" check only_installed || { echo "roger check by a bare name of the moved tree"; return 1; }
  "$roger" eval scripted --policy task --episodes 2 >/dev/null || { echo "roger eval of a shipped curriculum"; return 1; }
  "$roger" run "$tree/share/roger/scripts/quick.lua" --out "$work/quick" >"$work/quick.log" 2>&1 ||
    { cat "$work/quick.log"; echo "roger run of the installed quick.lua"; return 1; }
  local f
  for f in manifest.json summary.csv tables.md report.json index.html figure3.png figure4.svg figure5.png; do
    [ -s "$work/quick/$f" ] || { echo "the results folder has no $f"; return 1; }
  done
  [ "$(find "$work/quick/trials" -name result.json | wc -l)" -eq 24 ] || { echo "not 24 trial results"; return 1; }
  bash "$work/compare_results.sh" --golden "$work/golden" "$work/quick" ||
    { echo "the installed engine's results differ from tests/golden/quick"; return 1; }
  # A copy of the install resumes the folder the original made (its sources are the same files at
  # the same places of the copy), from a folder of one's own: a probe's was refused.
  cp -a "$tree" "$work/copied"
  "$work/copied/bin/roger" run "$work/copied/share/roger/scripts/quick.lua" --out "$work/quick" >"$work/resume.log" 2>&1 ||
    { cat "$work/resume.log"; echo "a copy of the install did not resume the original's results folder"; return 1; }
  # A copy of a shipped batch script in a folder of one's own still finds scripts/paper.lua.
  cp "$tree/share/roger/scripts/quick.lua" "$work/elsewhere/myquick.lua"
  "$roger" check myquick.lua >"$work/myquick.log" 2>&1 ||
    { cat "$work/myquick.log"; echo "roger check of a copy of quick.lua"; return 1; }
  grep -q "project folder: $tree/share/roger, installed beside the program" "$work/myquick.log" ||
    { cat "$work/myquick.log"; echo "roger check did not name the installed project folder"; return 1; }
  rm -rf "$work/copied"
  # Called by its bare name through PATH, as an installed program is, it reads its own tree too, and
  # a data_dir.txt in the current folder means nothing to it (found by a probe: glibc names such a
  # program by argv[0], "roger", and it was taken for the Python module and read the source tree).
  echo "$work/elsewhere" >"$work/elsewhere/data_dir.txt"
  (PATH="$tree/bin:$PATH" roger check myquick.lua >"$work/on_path.log" 2>&1) ||
    { cat "$work/on_path.log"; echo "roger on PATH: roger check of a copy of quick.lua"; return 1; }
  grep -q "project folder: $tree/share/roger, installed beside the program" "$work/on_path.log" ||
    { cat "$work/on_path.log"; echo "roger on PATH did not read its installed tree"; return 1; }
  rm "$work/elsewhere/data_dir.txt"
  # The docs' commands name docs/examples/...: installed, an error says where they are (found by
  # a probe: "no such file here or in the project", and nothing more).
  if "$roger" check docs/examples/corridor.lua >"$work/docs_example.log" 2>&1 ||
    ! grep -q "the documentation's files are installed apart from the project: $tree/share/doc/roger/examples/corridor.lua" \
      "$work/docs_example.log"; then
    cat "$work/docs_example.log"; echo "roger check of the docs' example path did not say where it is installed"; return 1
  fi
  "$roger" check "$tree/share/doc/roger/examples/corridor.lua" >"$work/docs_example.log" 2>&1 ||
    { cat "$work/docs_example.log"; echo "roger check of the installed docs' example"; return 1; }
  # The installed Python package reads the installed tree too, never the source tree it was built
  # from (found by a probe: every require went to the sources): a curriculum only the moved tree
  # has is found by its bare name.
  local module
  module=$(find "$tree/lib" -name '_roger*.so' 2>/dev/null | head -1)
  if [ -n "$module" ]; then
    cp "$tree/share/roger/curricula/paper.lua" "$tree/share/roger/curricula/only_installed_paper.lua"
    local python=/usr/bin/python3  # the system's, which the module is built for (.ci/install)
    [ -x "$python" ] || python=python3
    PYTHONPATH=$(dirname "$(dirname "$module")") "$python" -c "
import roger
env = roger.make('only_installed_paper', 'SG', 'B1')
env.reset(seed=1)
" >"$work/python.log" 2>&1 || { cat "$work/python.log"; echo "the installed Python package"; return 1; }
  elif [ "${CI:-}" = true ]; then
    echo "the install has no Python module (_roger*.so under lib/)"; return 1
  fi
}
export -f checks
export work tree

case $part in
  moved)
    checks || fail "the moved install"
    echo "PASSED: the moved install works" ;;
  hidden)
    # Empty folders over the source and build trees, in a mount namespace of this test alone.
    # A copy of the build tree's program, whose source tree is hidden too, says so (found by a
    # probe: it named a source tree that was no longer there as its project folder).
    cp "$build/engine/roger" "$work/build_tree_roger"
    unshare --mount --propagation private bash -c '
      mount -t tmpfs -o size=1m tmpfs "$1" && { [ "$2" = "${2#$1/}" ] && mount -t tmpfs -o size=1m tmpfs "$2" || true; } &&
      [ ! -e "$1/CMakeLists.txt" ] && checks &&
      "$work/build_tree_roger" --version | grep -q "the source tree this roger was built from, which is no longer there"' \
      _ "$source" "$build" || fail "the moved install, with the sources hidden"
    echo "PASSED: the moved install works with the source and build trees hidden" ;;
  deb)
    # The Debian package: the same files under /usr, what it needs declared, and a roger that works
    # from wherever it is unpacked.
    (cd "$build" && cpack -G DEB -B "$work/deb" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack -G DEB"; }
    deb=$(ls "$work"/deb/roger_*.deb 2>/dev/null | head -n 1)
    [ -n "$deb" ] || fail "cpack made no roger_*.deb"
    dpkg-deb -c "$deb" >"$work/deb.list"
    for f in ./usr/bin/roger ./usr/share/roger/scenarios/cluttered.lua ./usr/share/roger/curricula/lib/skills.lua \
             ./usr/share/roger/scripts/quick.lua ./usr/share/doc/roger/README.md; do
      grep -q " $f\$" "$work/deb.list" || fail "the package has no $f"
    done
    dpkg-deb -f "$deb" Depends | grep -q liblua5.4 || fail "the package does not depend on Lua's library"
    recommends=$(dpkg-deb -f "$deb" Recommends) suggests=$(dpkg-deb -f "$deb" Suggests)
    if grep -q "/dist-packages/roger/__init__.py\$" "$work/deb.list"; then
      # import roger needs numpy; its extras (gymnasium's judges, scripts/dqn.py) the rest.
      grep -q python3-numpy <<<"$recommends" || fail "the package does not recommend python3-numpy: '$recommends'"
      grep -q python3-torch <<<"$suggests" || fail "the package does not suggest python3-torch: '$suggests'"
    fi
    dpkg-deb -x "$deb" "$work/unpacked"
    (cd "$work/elsewhere" && "$work/unpacked/usr/bin/roger" check cluttered) >/dev/null || fail "roger of the unpacked package"
    echo "PASSED: the package $(basename "$deb") holds the install and works unpacked" ;;
esac
