#!/bin/bash
# Drives hemirad-gui by keyboard under Xvfb (run inside xvfb-run): Ctrl+O opens the file browser, a
# folder is typed and entered, then a file name in it, and the title must name the file. Keys are tapped
# (pressed and released within milliseconds, far shorter than a frame): ImGui 1.86 reads key state once
# a frame, and the GUI's KeyTaps keeps such a tap for the next frame. Holding a key instead lets ImGui
# repeat it (from 0.275 s on), and a repeated Return confirms again: 1.5 s holds failed in CI.
# usage: keyboard_open.sh HEMIRAD_GUI FOLDER FILE LOG
set -u
gui=$1 folder=$2 file=$3 log=$4
"$gui" --quit-after 30 > "$log" 2>&1 &
pid=$!
win=$(timeout 60 xdotool search --sync --onlyvisible --name '^Hemirad' | head -1)
[ -n "$win" ] || { echo "keyboard_open: no hemirad-gui window"; kill $pid; exit 1; }
sleep 2
xdotool windowfocus --sync "$win"
press() { xdotool keydown "$1" keyup "$1"; sleep 1; }  # one xdotool call: no pause between them
press ctrl+o
xdotool type --delay 40 "$folder"; sleep 0.5
press Return
xdotool type --delay 40 "$file"; sleep 0.5
press Return
sleep 3
echo "title: $(xdotool getwindowname "$win")"
wait $pid
echo "hemirad-gui exit $?"
