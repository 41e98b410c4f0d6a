#!/bin/sh
# palpa from the command line: one simulated board kept across commands, fingers set in people's
# terms, telemetry watched and recorded, a configuration saved that survives a restart.
set -eu
out=${1:-.}

palpa sim start                           # a simulated thesis-5finger board, its flash in a file
trap 'palpa sim stop >/dev/null' EXIT
palpa info

# Fingers are numbered from 1: a level, a deformation, a stiffness, a raw vacuum. Each prints
# what it became; --hold keeps the session (and so the fingers) for a second.
palpa set 1=L2 3=1.2mm 4=0.9N/mm 5=-10kPa --hold 1

# Telemetry as JSON lines: every line's pressures, every finger's output in mm or N/mm.
palpa --json monitor --rate 2 --duration 1 | head -n 1

# A recording: a row per sample, UTC and board time, a column per line and per finger.
palpa record "$out/run.csv" --duration 1
sed -n '2,3p' "$out/run.csv" | cut -c 1-100

# A configuration change is live at once, and kept across a restart once saved.
palpa config set board.host_timeout_us=200000
palpa config save
palpa sim stop
palpa sim start >/dev/null
palpa info | grep '^configuration'
palpa --json config show | grep -q '"host_timeout_us":200000'
palpa config factory-reset

# Scenes: the three-cube phantom's tissue file, a scene drawn, a recorded pass played to the board.
palpa scene phantom --preset thesis-three-cube --out "$out/three.json"
scene=$(dirname "$0")/scene_three_cube.json
palpa scene show "$scene" --at 60,12 --out "$out/scene.svg"
printf 'time_s,x_mm,y_mm,force_n\n0,45,12,1\n0.2,55,12,1\n0.4,65,12,1\n' > "$out/pass.csv"
palpa render "$scene" --input "$out/pass.csv" --record "$out/render.csv"

palpa estop                               # every line safe, latched
palpa clear
