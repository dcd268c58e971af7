#!/bin/bash
# Taps keys in hemirad-gui under Xvfb (run inside xvfb-run), then lets --quit-after end it: the GUI
# prints its log and the panels of its last frame. Each tap is a press and release in one xdotool call,
# then a wait of several frames' time (see keyboard_open.sh for why). A step may also be
# type:TEXT (typed), click:X,Y (a left click there), dblclick:X,Y (a double-click at human speed,
# 150 ms between the clicks: ImGui's limit is 300 ms), hold:X,Y,S (the button held S seconds),
# wheel:X,Y,N (N steps of the wheel down there), drag:X,Y,X2,Y2 (a left drag), clickaway:X,Y (a
# click there, the pointer moving on at once), enter:TEXT (typed fast, then Return) or wait:S.
# usage: keyboard_keys.sh HEMIRAD_GUI LOG SECONDS "GUI ARGUMENTS" STEP...
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
for step in "$@"; do
    case $step in
        type:*) xdotool type --delay 40 "${step#type:}" ;;
        click:*) xy=${step#click:}; xdotool mousemove --window "$win" ${xy/,/ }; sleep 1; xdotool click 1 ;;
        dblclick:*) xy=${step#dblclick:}; xdotool mousemove --window "$win" ${xy/,/ }; sleep 1; xdotool click --repeat 2 --delay 150 1 ;;
        wheel:*) IFS=, read -r x y n <<< "${step#wheel:}"; xdotool mousemove --window "$win" "$x" "$y"; sleep 1
                 xdotool click --repeat "$n" --delay 50 5 ;;
        drag:*) IFS=, read -r x y x2 y2 <<< "${step#drag:}"; xdotool mousemove --window "$win" "$x" "$y"; sleep 1
                xdotool mousedown 1; sleep 0.2
                for k in 1 2 3 4 5 6 7 8 9 10; do
                    xdotool mousemove --window "$win" $((x + (x2 - x) * k / 10)) $((y + (y2 - y) * k / 10)); sleep 0.05
                done
                sleep 0.2; xdotool mouseup 1 ;;
        clickaway:*) xy=${step#clickaway:}; xdotool mousemove --window "$win" ${xy/,/ }; sleep 1
                     xdotool click 1 mousemove_relative 40 0 mousemove_relative 40 0 ;;
        wait:*) sleep "${step#wait:}" ;;
        enter:*) xdotool type --delay 5 "${step#enter:}"; xdotool key Return ;;
        hold:*) IFS=, read -r x y held <<< "${step#hold:}"; xdotool mousemove --window "$win" "$x" "$y"; sleep 1
                xdotool mousedown 1; sleep "$held"; xdotool mouseup 1 ;;
        *) xdotool keydown "$step" keyup "$step" ;;
    esac
    sleep 5
done
wait $pid
echo "hemirad-gui exit $?"
