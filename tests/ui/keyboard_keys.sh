#!/bin/bash
# Taps keys in hemirad-gui under Xvfb (run inside xvfb-run), then lets --quit-after end it: the GUI
# prints its log and the panels of its last frame. Each tap is a press and release in one xdotool call,
# then a wait of several frames' time (see keyboard_open.sh for why).
# usage: keyboard_keys.sh HEMIRAD_GUI LOG SECONDS "GUI ARGUMENTS" KEY...
set -u
gui=$1 log=$2 seconds=$3 arguments=$4
shift 4
# shellcheck disable=SC2086  # the arguments are words
"$gui" $arguments --quit-after "$seconds" > "$log" 2>&1 &
pid=$!
win=$(timeout 60 xdotool search --sync --onlyvisible --name '^Hemirad' | head -1)
[ -n "$win" ] || { echo "keyboard_keys: no hemirad-gui window"; kill $pid; exit 1; }
sleep 2
xdotool windowfocus --sync "$win"
for key in "$@"; do
    xdotool keydown "$key" keyup "$key"
    sleep 5
done
wait $pid
echo "hemirad-gui exit $?"
