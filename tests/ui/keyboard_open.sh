#!/bin/bash
# Drives hemirad-gui by keyboard under Xvfb (run inside xvfb-run): Ctrl+O opens the file browser, a
# folder is typed and entered, then a file name in it, and the title must name the file. Keys are tapped
# (pressed and released within milliseconds, far shorter than a frame): ImGui 1.86 reads key state once
# a frame, and the GUI's KeyTaps keeps such a tap for the next frame. Holding a key instead lets ImGui
# repeat it (from 0.275 s on), and a repeated Return confirms again: 1.5 s holds failed in CI.
# Each step waits several frames' time before the next (5 s: a frame took 0.65 s in the sanitize
# stage of a busy CI run), since characters typed before the browser's path field is active are
# lost (ImGui drops the characters of a frame in which no text field takes them).
# usage: keyboard_open.sh HEMIRAD_GUI FOLDER FILE LOG
set -u
gui=$1 folder=$2 file=$3 log=$4
"$gui" --quit-after 60 > "$log" 2>&1 &
pid=$!
win=$(timeout 60 xdotool search --sync --onlyvisible --name '^Hemirad' | head -1)
[ -n "$win" ] || { echo "keyboard_open: no hemirad-gui window"; kill $pid; exit 1; }
sleep 2
xdotool windowfocus --sync "$win"
step=5
press() { xdotool keydown "$1" keyup "$1"; sleep $step; }  # one xdotool call: no pause between them
press ctrl+o
xdotool type --delay 40 "$folder"; sleep $step
press Return
xdotool type --delay 40 "$file"; sleep $step
press Return
echo "title: $(xdotool getwindowname "$win")"
xdotool keydown ctrl+q keyup ctrl+q  # quit now (--quit-after is the fallback)
wait $pid
echo "hemirad-gui exit $?"
