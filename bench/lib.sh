# shellcheck shell=bash
# Shared by the bench/run_*.sh scripts: `source bench/lib.sh` once the script has changed to the
# repository root. What a recorded section's provenance line is made of, and the scratch folder.

# bench_commit PATH...: the short commit, with "+changes" if PATH... differ from it in the work
# tree (the numbers were then measured with code no commit holds).
bench_commit() { echo "$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- "$@" || echo "+changes")"; }

# bench_cpu: the CPU's model name.
bench_cpu() { grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'; }

# bench_workdir: a scratch folder in $work, removed when the script exits however it exits.
bench_workdir() {
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
}

# bench_setup BUILD TARGET...: $build = BUILD, TARGET... built in it (quietly), and the scratch
# folder (bench_workdir). The scripts that run tools on scenes start with it.
bench_setup() {
  build=$1
  shift
  cmake --build "$build" --target "$@" -j 2 >/dev/null
  bench_workdir
}
