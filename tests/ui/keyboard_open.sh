#!/bin/bash
# Drives hemirad-gui by keyboard under Xvfb (run inside xvfb-run): Ctrl+O opens the file browser, a
# folder is typed and entered, then a file name in it, and the title must name the file. Keys are held
# for a while: ImGui 1.86 reads key state once a frame, so a press shorter than a frame can be missed
# (under ASan on a busy 2-core machine a frame took 0.7 s, and a 0.5 s press was lost).
# usage: keyboard_open.sh HEMIRAD_GUI FOLDER FILE LOG
set -u
gui=$1 folder=$2 file=$3 log=$4
"$gui" --quit-after 40 > "$log" 2>&1 &
pid=$!
win=$(timeout 60 xdotool search --sync --onlyvisible --name '^Hemirad' | head -1)
[ -n "$win" ] || { echo "keyboard_open: no hemirad-gui window"; kill $pid; exit 1; }
sleep 2
xdotool windowfocus --sync "$win"
press() { xdotool keydown "$1"; sleep 1.5; xdotool keyup "$1"; sleep 1; }
press ctrl+o
xdotool type --delay 40 "$folder"; sleep 0.5
press Return
xdotool type --delay 40 "$file"; sleep 0.5
press Return
sleep 3
echo "title: $(xdotool getwindowname "$win")"
wait $pid
echo "hemirad-gui exit $?"
