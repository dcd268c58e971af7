#!/usr/bin/env bash
# Installs the Debian packages Hemirad needs that are missing; idempotent and silent when none is.
# While apt works, one progress line per package goes to stderr (rewritten in place on a terminal);
# apt's full output is kept in one log file ($HEMIRAD_DEPS_LOG, default ~/.cache/hemirad/install-deps.log).
set -euo pipefail

packages=(
  cmake g++ make pkg-config ccache
  libembree-dev libeigen3-dev doctest-dev libstb-dev
  libglfw3-dev libegl-dev libegl-mesa0 libgl-dev libosmesa6-dev libimgui-dev
  xvfb xdotool python3-matplotlib
  libopenmpi-dev openmpi-bin petsc-dev time libtomlplusplus-dev libopenblas-openmp-dev
  pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest python3-setuptools
)

# `install-deps.sh fuzz` adds clang and its fuzzer/sanitizer runtime for `make fuzz`.
if [ "${1:-}" = "fuzz" ]; then packages+=(clang libclang-rt-14-dev libomp-dev); fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  case "$status" in *" ok installed") ;; *) missing+=("$p") ;; esac
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi

# One log, rewritten by each run that installs something: a section per apt-get call.
log=${HEMIRAD_DEPS_LOG:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/hemirad/install-deps.log}
if ! { mkdir -p "$(dirname "$log")" && : >"$log"; } 2>/dev/null; then
  log=$(mktemp -t hemirad-install-deps.XXXXXX.log)
fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]} (apt's output: $log)" >&2

# progress: reads apt's output and reports on stderr: a line per phase (the download size, what was
# fetched) and a line per package unpacked and set up, numbered against the total that apt announces.
# On a terminal the package lines (downloads too) rewrite one line in place. It never fails, so that
# a success of apt cannot look like a failure of the pipeline.
inplace=0
[ -t 2 ] && inplace=1
progress() {
  local line word size suite arch total=0 got=0 unpacked=0 set_up=0 open=0 cols=79
  if [ $inplace -eq 1 ]; then cols=$(( $(tput cols 2>/dev/null || echo 80) - 1 )); fi
  show() {  # show phase|package|download MESSAGE
    local msg="install-deps: $2"
    if [ $inplace -eq 1 ] && [ "$1" != phase ]; then
      printf '\r\033[K%s' "${msg:0:cols}" >&2
      open=1
    elif [ "$1" != download ]; then
      if [ $open -eq 1 ]; then printf '\r\033[K' >&2; open=0; fi
      printf '%s\n' "$msg" >&2
    fi
  }
  count() { if [ $total -gt 0 ]; then echo "[$1/$total]"; else echo "[$1]"; fi; }
  while IFS= read -r line || [ -n "$line" ]; do
    case "$line" in
      *" newly installed, "*)  # "U upgraded, N newly installed, R to remove and K not upgraded."
        word=${line%% upgraded,*}
        size=${line#*upgraded, }; size=${size%% newly installed*}
        if [[ $word =~ ^[0-9]+$ && $size =~ ^[0-9]+$ ]]; then total=$((word + size)); fi ;;
      "Need to get "*)
        size=${line#Need to get }; size=${size%% of archives*}
        show phase "apt-get: $total packages with their dependencies, $size to download" ;;
      Get:*)
        got=$((got + 1))
        read -r _ _ suite arch word _ <<<"$line"  # Get:K URL SUITE ARCH PACKAGE VERSION [SIZE]
        case "$word" in "["*) word="$suite $arch" ;; esac  # apt-get update: Get:K URL SUITE FILE [SIZE]
        show download "$(count $got) downloading ${word%%:*}" ;;
      Fetched*)
        show phase "apt-get: ${line%.}" ;;
      "Unpacking "*)
        unpacked=$((unpacked + 1)); read -r _ word _ <<<"$line"
        show package "$(count $unpacked) unpacking ${word%%:*}" ;;
      "Setting up "*)
        set_up=$((set_up + 1)); read -r _ _ word _ <<<"$line"
        show package "$(count $set_up) setting up ${word%%:*}" ;;
    esac
  done
  if [ $open -eq 1 ]; then printf '\n' >&2; fi
  return 0
}

# apt_section TITLE ARGS...: runs `apt-get ARGS` with progress, appending its output to the log
# under a header; returns apt-get's own exit status (PIPESTATUS[0], not the filter's).
section_starts=()
apt_section() {
  local title=$1 rc=0
  shift
  section_starts+=("$(( $(wc -l <"$log") + 1 )):$title")
  printf '==== %s (%s)\n' "$title" "$(date '+%F %T')" >>"$log"
  $sudo env LC_ALL=C DEBIAN_FRONTEND=noninteractive apt-get "$@" 2>&1 | tee -a "$log" | progress \
    || rc=${PIPESTATUS[0]}
  printf '==== %s: exit status %d\n\n' "$title" "$rc" >>"$log"
  return "$rc"
}

# print_log_tail N: the last N lines of every section of the log, each under its header.
print_log_tail() {
  local i start end title total
  total=$(wc -l <"$log")
  for i in "${!section_starts[@]}"; do
    start=${section_starts[i]%%:*}
    title=${section_starts[i]#*:}
    if [ $((i + 1)) -lt ${#section_starts[@]} ]; then  # each section ends with a blank line
      end=$(( ${section_starts[i + 1]%%:*} - 2 ))
    else
      end=$((total - 1))
    fi
    echo "---- $title: last lines" >&2
    sed -n "$((start + 1)),${end}p" "$log" | tail -n "$1" >&2
  done
}

options=(-y -q --no-install-recommends -o Dpkg::Progress-Fancy=0 -o Dpkg::Use-Pty=0
         -o APT::Color=0 -o DPkg::Lock::Timeout=120)
if apt_section "apt-get install ${missing[*]}" install "${options[@]}" "${missing[@]}"; then
  echo "install-deps: done" >&2
  exit 0
fi

echo "install-deps: apt-get install failed; updating the package lists and trying again" >&2
apt_section "apt-get update" update -q -o APT::Color=0 -o DPkg::Lock::Timeout=120 || true
if apt_section "apt-get install ${missing[*]} (after apt-get update)" install "${options[@]}" "${missing[@]}"; then
  echo "install-deps: done" >&2
  exit 0
fi

echo "install-deps: apt-get install failed twice; the full output is in $log" >&2
print_log_tail 15
exit 1
