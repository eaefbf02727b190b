# Sourced by the walkthrough checks: runs a page's ```sh blocks in order in a scratch copy of the
# repository's layout, each block in one shell, and checks that each line of the plain ```
# block that follows a ```sh block appears in that block's output.
#   setup_scratch <source dir> <bin dir> <scratch dir>: build/bin -> the built tools; config/,
#     maps/ linked; data/ copied
#   run_doc_blocks <page> <scratch dir> <least number of sh blocks>: sets `fail` to 1 when an
#     expected line is missing; exits 1 when a block fails
setup_scratch() {
  local src=$1 bin=$2 scratch=$3
  rm -rf "$scratch"
  mkdir -p "$scratch/build"
  ln -s "$bin" "$scratch/build/bin"
  ln -s "$src/config" "$scratch/config"
  ln -s "$src/maps" "$scratch/maps"
  cp -a "$src/data" "$scratch/data"
}

run_doc_blocks() {
  local doc=$1 scratch=$2 least=$3 n k
  # Split the page: block k's commands into cmd_k.sh, the expected output after it into exp_k.txt.
  awk -v dir="$scratch" '
    /^```sh$/ { k++; out = dir "/cmd_" k ".sh"; printf "" > out; inblock = 1; next }
    /^```$/ && !inblock && k > 0 && !seen[k] { out = dir "/exp_" k ".txt"; printf "" > out; inblock = 2; seen[k] = 1; next }
    /^```/ { if (inblock) { inblock = 0; next } else { inblock = 3; next } }
    inblock == 1 || inblock == 2 { print >> out }
  ' "$doc"
  n=$(ls "$scratch"/cmd_*.sh | wc -l)
  if [ "$n" -lt "$least" ]; then
    echo "FAIL: $doc has only $n sh blocks"; exit 1
  fi
  for k in $(seq 1 "$n"); do
    echo "== block $k"
    cat "$scratch/cmd_$k.sh"
    if ! (cd "$scratch" && bash -euo pipefail "cmd_$k.sh") > "$scratch/out_$k.txt" 2> "$scratch/err_$k.txt"; then
      echo "FAIL: block $k failed:"; cat "$scratch/out_$k.txt" "$scratch/err_$k.txt"; exit 1
    fi
    cat "$scratch/out_$k.txt"
    if [ -f "$scratch/exp_$k.txt" ]; then
      while IFS= read -r line; do
        [ -z "$line" ] && continue
        if ! grep -qxF -- "$line" "$scratch/out_$k.txt"; then
          echo "FAIL: block $k did not print: $line"; fail=1
        fi
      done < "$scratch/exp_$k.txt"
    fi
  done
}
