# Sourced by the bench scripts with BUILD_DIR: strict mode, $hemirad (BUILD_DIR/hemirad), $root (the
# repository) and $work (a temporary folder removed on exit).
set -euo pipefail
hemirad="$(cd "${1:-build}" && pwd)/hemirad"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
