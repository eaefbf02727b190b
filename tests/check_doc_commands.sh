#!/usr/bin/env bash
# Runs every shell command of the fenced ```sh (```bash, ```shell) blocks of README.md and
# docs/*.md, each block's commands in order in one shell, in a fresh copy of the repository
# (its tracked and unignored files) whose build/ holds links to this build's bin/, libsemloc/,
# libsemloc_tools/, bench/ and tests/. A command that fails fails the test, naming the file, the
# line and the command. How the commands are run (docs/testing.md, "The documented commands"):
# - `/tmp/` in a command is the copy's own tmp/ (a fresh one: nothing from an earlier run,
#   nothing shared with a run beside it); the message shows the command as written;
# - SEMLOC_BENCHMARK_RUNS=1: semloc-benchmark runs each documented benchmark with 1 run
#   (it says so on stderr) instead of its ini's 20 to 100 (minutes to an hour each);
# - BENCHMARK_MIN_TIME=0.01: Google Benchmark's programs (build/bench/) time each case for
#   0.01 s instead of 0.5 s, unless the command sets --benchmark_min_time itself;
# - commands that cannot run here are checked for syntax only (bash -n), each kind with its
#   reason below (syntaxOnlyReason); none is skipped silently: the log lists each one;
# - the build steps at the head of an `&&` chain (bash .ci/setup, cmake -S, cmake --build)
#   are the ones that made this build: they are checked for syntax and the rest of the
#   chain runs;
# - docs/your-own-data.md and docs/auv-own-log.md are run by walkthrough_your_own_data
#   (check_walkthrough.sh) and walkthrough_auv_own_log (check_auv_walkthrough.sh), with their
#   outputs checked, so not again here;
# - a block whose first line is a comment starting `# long` reproduces a figure of real data
#   over many minutes: checked for syntax only, unless DOC_COMMANDS_LONG=1 (then it runs).
# A command of the tools (a line starting `build/bin/`, `bash `, `cmake `, `ctest `) in a
# fenced block that is not a shell block fails too: it would escape this test.
# Usage: check_doc_commands.sh <source dir> <build dir> <scratch dir>
#   DOC_COMMANDS_PAGES="docs/tools.md" (paths in the source dir) runs those pages only;
#   DOC_COMMANDS_LONG=1 runs the long blocks too.
set -euo pipefail
src=$(cd "$1" && pwd) build=$(cd "$2" && pwd) scratch=$3
pages=${DOC_COMMANDS_PAGES:-$(cd "$src" && ls README.md docs/*.md | grep -Ev '^docs/(your-own-data|auv-own-log)\.md$')}
rm -rf "$scratch"
mkdir -p "$scratch"
scratch=$(cd "$scratch" && pwd)
case "$scratch" in *[[:space:]]*) echo "FAIL: the scratch path '$scratch' holds a blank"; exit 1 ;; esac
repo="$scratch/repo" tmp="$scratch/tmp"
mkdir -p "$repo/build" "$tmp" "$scratch/cmd"

# The copy: what git tracks or would track (not the build trees, not results/).
if git -C "$src" rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  (cd "$src" && git ls-files -z --cached --others --exclude-standard |
     xargs -0 -I{} sh -c '[ -e "{}" ] && printf "%s\0" "{}"' | tar --null -T - -cf -) |
    (cd "$repo" && tar -xf -)
else
  (cd "$src" && tar --exclude='./build*' --exclude=./results --exclude=./.git -cf - .) |
    (cd "$repo" && tar -xf -)
fi
for d in bin libsemloc libsemloc_tools bench tests; do
  [ -e "$build/$d" ] && ln -s "$build/$d" "$repo/build/$d"
done

# Why a command is checked for syntax only (empty: it runs).
syntaxOnlyReason() {
  case "$1" in
    "bash .ci/setup"*) echo "installs Debian packages (root, network)" ;;
    "cmake -S "* | "cmake --build "*) echo "builds the tree: this test runs in the build it makes" ;;
    "cmake --install "*) echo "installs outside the repository; embed_example_against_installed_tree installs the tree and builds against it" ;;
    "ctest "*) echo "runs the suite this test is part of" ;;
    *"sbatch "*) echo "submits jobs to a Slurm cluster (none here)" ;;
    "bash tests/sanitize.sh"* | "bash tests/fuzz/run.sh"*) echo "builds and runs the suite in another tree (ASan + UBSan, libFuzzer): tens of minutes; CI runs it after the suite (.ci/run)" ;;
    *"build-asan/fuzz/"*) echo "runs a libFuzzer target of build-asan/fuzz/, which tests/fuzz/run.sh builds in another tree (CI runs it after the suite)" ;;
    *) echo "" ;;
  esac
}

# Split the pages: one file per command (continuation lines and heredocs joined), its page
# and line in a list, block by block.
awk -v dir="$scratch/cmd" -v srcdir="$src/" '
  FNR == 1 { page = FILENAME; sub("^" srcdir, "", page); fence = 0; heredoc = "" }
  /^```/ && !fence {
    fence = 1; lang = substr($0, 4); shell = (lang == "sh" || lang == "bash" || lang == "shell")
    if (shell) { block++; first = 1 }
    cont = 0; next
  }
  /^```$/ && fence && heredoc == "" { fence = 0; next }
  fence && !shell {
    if ($0 ~ /^(build\/bin\/|bash |cmake |ctest )/) { print page ":" FNR ": a command in a ```" lang " block" > (dir "/misplaced") }
    next
  }
  fence && shell {
    if (heredoc != "") { print >> cur; if ($0 == heredoc) { heredoc = "" }; next }
    if (!cont) {
      if ($0 ~ /^[ \t]*$/) next
      if (first && $0 ~ /^# long/) { print block > (dir "/long") }
      first = 0
      n++; cur = sprintf("%s/%04d.sh", dir, n); printf "" > cur
      print n "\t" block "\t" page ":" FNR > (dir "/list")
    }
    print >> cur
    cont = ($0 ~ /\\$/)
    if (match($0, /<<-?[ ]*\047?[A-Za-z_]+\047?/)) {
      heredoc = substr($0, RSTART, RLENGTH); gsub(/^<<-?[ ]*|\047/, "", heredoc)
    }
  }
' $(for p in $pages; do echo "$src/$p"; done)

fail=0
if [ -s "$scratch/cmd/misplaced" ]; then
  echo "FAIL: commands in fenced blocks that are not shell blocks (not run):"
  cat "$scratch/cmd/misplaced"; fail=1
fi
[ -s "$scratch/cmd/list" ] || { echo "FAIL: no shell block found"; exit 1; }

# One runner per block: its commands in order in one shell (a `cd` holds for the block).
export SEMLOC_BENCHMARK_RUNS=1 BENCHMARK_MIN_TIME=0.01 PATH="$build/bin:$PATH"
ran=0 checked=0 t0=$(date +%s)
for b in $(cut -f2 "$scratch/cmd/list" | sort -un); do
  runner="$scratch/cmd/block_$b.sh"
  printf 'set -eo pipefail\ncd %q\n' "$repo" > "$runner"
  printf "trap 'rc=\$?; [ \$rc -eq 0 ] || echo \"FAIL: \$where: exit status \$rc: \$what\"' EXIT\n" >> "$runner"
  long=""
  if [ "${DOC_COMMANDS_LONG:-0}" != 1 ] && grep -qx "$b" "$scratch/cmd/long" 2>/dev/null; then
    long="a long reproduction on real data (DOC_COMMANDS_LONG=1 runs it)"
  fi
  while IFS=$'\t' read -r n blk where; do
    [ "$blk" = "$b" ] || continue
    printf -v f '%s/%04d.sh' "$scratch/cmd" "$n"
    what=$(tr '\n' ' ' < "$f")
    bash -n "$f" 2> "$f.syntax" || { echo "FAIL: $where: not valid bash: $what"; cat "$f.syntax"; fail=1; continue; }
    # The build steps at the head of a chain: this build made them.
    rest=$(cat "$f")
    while reason=$(syntaxOnlyReason "$rest"); [ -n "$reason" ]; do
      head=${rest%% && *}
      case "$head" in "bash .ci/setup"* | "cmake -S "* | "cmake --build "*) ;; *) break ;; esac
      echo "syntax only ($where): $head  -- $reason"; checked=$((checked + 1))
      [ "$head" = "$rest" ] && { rest=""; break; }
      rest=${rest#* && }
    done
    [ -n "$rest" ] || continue
    reason=$(syntaxOnlyReason "$rest")
    [ -n "$reason" ] || reason=$long
    if [ -n "$reason" ]; then
      echo "syntax only ($where): $rest  -- $reason"; checked=$((checked + 1)); continue
    fi
    printf '%s\n' "$rest" | sed "s#/tmp/#$tmp/#g" > "$f.run"
    printf 'where=%q what=%q t=$SECONDS\n. %q\nprintf "== %%s (%%d s): %%s\\n" "$where" $((SECONDS - t)) "$what"\n' "$where" "$what" "$f.run" >> "$runner"
    ran=$((ran + 1))
  done < "$scratch/cmd/list"
  if ! bash "$runner" > "$scratch/cmd/block_$b.log" 2>&1; then
    cat "$scratch/cmd/block_$b.log" | tail -40
    fail=1
  else
    grep '^== ' "$scratch/cmd/block_$b.log" || true
  fi
done
echo "$ran commands run, $checked checked for syntax only, in $(( $(date +%s) - t0 )) s"
[ "$fail" -eq 0 ] && echo "doc commands OK"
exit "$fail"
