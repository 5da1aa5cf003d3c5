#!/usr/bin/env bash
# `hlod view` in a real window under a virtual X server: the window opens, holding W flies the
# camera forward, Escape quits, and --record writes a camera path whose last key has moved; an
# interrupt (SIGTERM here: a background job ignores SIGINT; Ctrl-C takes the same way) quits too,
# the flight still recorded, with the status of an interrupted run (143).
# Exit 77 (skipped) when Xvfb or xdotool is missing.
set -u
hlod=$1
command -v Xvfb >/dev/null && command -v xdotool >/dev/null || { echo "SKIP: Xvfb/xdotool absent"; exit 77; }
dir=$(mktemp -d)
xvfb=
trap '[ -n "$xvfb" ] && kill "$xvfb" 2>/dev/null; rm -rf "$dir"' EXIT
"$hlod" build "$HLOD_SOURCE_DIR/samples/city" -o "$dir/city.hlod" >/dev/null || { echo "FAIL: build"; exit 1; }

cat > "$dir/drive.sh" <<EOS
#!/usr/bin/env bash
# \$1: the recording; \$2: how to quit, escape (the key) or term (SIGTERM).
# Under the ASan pass, leak checks off for the window only: the GLX/X11 stack under Xvfb leaks
# 112 bytes at exit, in libraries without frame pointers (hlod's GL code is leak-checked by the
# headless EGL tests).
ASAN_OPTIONS="\${ASAN_OPTIONS:+\$ASAN_OPTIONS:}detect_leaks=0" \\
  "$hlod" view "$dir/city.hlod" --record "\$1" --width 320 --height 200 > "$dir/view.log" 2>&1 &
pid=\$!
for i in \$(seq 1 120); do
  wid=\$(xdotool search --pid \$pid 2>/dev/null | head -1)
  [ -n "\$wid" ] && break
  sleep 0.5
done
[ -n "\$wid" ] || { echo "FAIL: no window"; kill \$pid; exit 1; }
for i in \$(seq 1 120); do grep -q "^up axis" "$dir/view.log" && break; sleep 0.5; done  # hlod0 loaded: the loop starts
sleep 2
xdotool mousemove --window \$wid 160 100  # no window manager: focus follows the pointer
xdotool windowfocus \$wid 2>/dev/null
xdotool keydown w; sleep 2; xdotool keyup w
if [ "\$2" = escape ]; then xdotool key Escape; else kill -TERM \$pid; fi
for i in \$(seq 1 60); do kill -0 \$pid 2>/dev/null || break; sleep 0.5; done
kill -0 \$pid 2>/dev/null && { echo "FAIL: \$2 did not quit"; kill \$pid; exit 1; }
wait \$pid
EOS
chmod +x "$dir/drive.sh"
# Xvfb picks a free display itself (-displayfd: no race with another server, as `xvfb-run -a`
# has); the window starts once the display answers, and -noreset keeps the server from resetting
# when that probe disconnects (connections made during a reset fail: "Failed to open display").
Xvfb -displayfd 3 -nolisten tcp -noreset -screen 0 640x400x24 3>"$dir/display" 2>"$dir/xvfb.log" &
xvfb=$!
for i in $(seq 1 60); do
  [ -s "$dir/display" ] && DISPLAY=:$(cat "$dir/display") xdotool getdisplaygeometry >/dev/null 2>&1 && break
  sleep 0.5
done
export DISPLAY=:$(cat "$dir/display" 2>/dev/null)
xdotool getdisplaygeometry >/dev/null 2>&1 || { echo "FAIL: Xvfb did not answer in 30 s"; cat "$dir/xvfb.log"; exit 1; }
"$dir/drive.sh" "$dir/rec.path" escape ||
  { echo "FAIL: view exited non-zero"; cat "$dir/view.log"; echo "Xvfb's log:"; cat "$dir/xvfb.log"; exit 1; }
[ -s "$dir/rec.path" ] || { echo "FAIL: no recording"; exit 1; }
first=$(grep -v '^#' "$dir/rec.path" | sed -n 2p | awk '{print $2, $3, $4}')
last=$(tail -1 "$dir/rec.path" | awk '{print $2, $3, $4}')
[ "$first" != "$last" ] || { echo "FAIL: camera did not move ($first)"; exit 1; }
"$dir/drive.sh" "$dir/term.path" term
status=$?
[ $status = 143 ] || { echo "FAIL: SIGTERM: status $status, not 143"; cat "$dir/view.log"; exit 1; }
keys=$(grep -v '^#' "$dir/term.path" 2>/dev/null | tail -n +2 | wc -l)
[ "$keys" -ge 2 ] || { echo "FAIL: SIGTERM lost the flight ($keys keys)"; cat "$dir/view.log"; exit 1; }
echo "PASS: window opened, W moved the camera from ($first) to ($last), Escape quit, path recorded; SIGTERM quit with 143 and recorded $keys keys"
