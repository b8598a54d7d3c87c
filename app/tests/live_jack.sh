#!/usr/bin/env bash
# The standalone against a JACK dummy server (no sound card): the example voice is played into
# its input and its output recorded (app/tests/jack_play.py), VMC is received on UDP by a
# third-party receiver (app/tests/vmc_receiver.py), and the output must hold inserted breaths
# (app/tests/check_live.py). Mode `gui`: under Xvfb with the editor window, and a screenshot
# taken after the voice must show the timeline with breaths. Mode `headless`: `--no-gui`.
# Then the app must quit on Ctrl+C in the rest pose (both modes); headless, also on SIGTERM with
# the JACK server stopped (SIGSTOP), and a third app must say so when the server stops under it.
#
# Usage: app/tests/live_jack.sh gui|headless APP_BINARY PYTHON_WITH_DEPS
# Needs jackd (jackd2), and for `gui` Xvfb, Mesa and ImageMagick (`.ci/run` installs them).
# Artefacts (recorded output, screenshot) go to target/live-test/.
set -euo pipefail
mode="$1"; app="$2"; py="$3"
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$root/target/live-test/$mode"
mkdir -p "$out"
voice="$root/assets/examples/voice.wav"
server="pneuma-ci-$$"
export JACK_DEFAULT_SERVER="$server"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT

listen_last() {  # [--require-motion]: starts the last-frame receiver on the VMC port
  rm -f "$out/last.ready"
  "$py" "$here/last_head.py" --port "$vmc_port" --ready-file "$out/last.ready" --timeout-s 20 \
    --quiet-s 3 "$@" >"$out/last.json" &
  last_pid=$!
  for _ in $(seq 100); do [ -f "$out/last.ready" ] && break; sleep 0.1; done
}
quit_app() {  # SIGNAL PID LOG: sends it, waits at most 5 s; prints the seconds, fails on a hang
  local t0 t1
  t0="$(date +%s.%N)"
  kill "-$1" "$2"
  for _ in $(seq 50); do kill -0 "$2" 2>/dev/null || break; sleep 0.1; done
  t1="$(date +%s.%N)"
  if kill -0 "$2" 2>/dev/null; then
    echo "pneuma-app did not quit within 5 s of SIG$1; its log:" >&2; cat "$3" >&2; exit 1
  fi
  set +e; wait "$2"; quit_rc=$?; set -e
  [ "$quit_rc" = 0 ] || { echo "pneuma-app exited $quit_rc after SIG$1; its log:" >&2; cat "$3" >&2; exit 1; }
  quit_s="$(python3 -c "print(f'{$t1 - $t0:.2f}')")"
}
rest_received() {  # LABEL: the receiver's last head must be the rest pose
  if ! wait "$last_pid"; then
    echo "$1: the avatar was not left in its rest pose: $(cat "$out/last.json")" >&2; exit 1
  fi
}
wait_ports_gone() {
  for _ in $(seq 100); do jack_lsp 2>/dev/null | grep -q '^pneuma:' || return 0; sleep 0.1; done
  echo "the JACK server still lists pneuma's ports" >&2; exit 1
}
start_app() {  # LOG ARGS...: starts an app and waits for its JACK ports
  local log="$1"; shift
  "$app" "$@" >"$log" 2>&1 &
  app_pid=$!
  pids+=("$app_pid")
  for _ in $(seq 100); do jack_lsp 2>/dev/null | grep -q '^pneuma:input_1$' && break; sleep 0.1; done
  jack_lsp 2>/dev/null | grep -q '^pneuma:input_1$' || {
    echo "pneuma-app did not register its JACK ports; its log:" >&2; cat "$log" >&2; exit 1; }
}

# A JACK server killed without its cleanup (an interrupted run) leaves its entry in the shared
# registry, and jackd refuses to start once the registry is full ("Too many servers already
# active"): with no jackd running, stale entries are removed first.
if ! pgrep -x jackd >/dev/null 2>&1; then
  rm -f /dev/shm/jack-shm-registry /dev/shm/jack_sem.* /dev/shm/jack_db-* /dev/shm/jack-[0-9]* 2>/dev/null || true
fi

# A dummy JACK server at the voice's rate (16 kHz), 256-sample periods.
jackd --no-realtime -n "$server" -d dummy -r 16000 -p 256 >"$out/jackd.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do jack_lsp >/dev/null 2>&1 && break; sleep 0.1; done
jack_lsp >/dev/null 2>&1 || { echo "jackd did not start; see $out/jackd.log" >&2; exit 1; }

vmc_port="$(python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
args=(--osc-port "$vmc_port" --osc-format vmc)
if [ "$mode" = gui ]; then
  display=":$((90 + $$ % 9))"
  Xvfb "$display" -screen 0 1280x800x24 -nolisten tcp >"$out/xvfb.log" 2>&1 &
  pids+=($!)
  export DISPLAY="$display" LIBGL_ALWAYS_SOFTWARE=1
  for _ in $(seq 50); do xdpyinfo >/dev/null 2>&1 && break; sleep 0.1; done
else
  args+=(--no-gui)
  unset DISPLAY || true
fi

# The VMC receiver: the voice lasts 25 s; 1000 bundles is about 8 s of it at 120 frames/s.
"$py" "$here/vmc_receiver.py" --port "$vmc_port" --bundles 1000 --timeout-s 60 \
  --ready-file "$out/vmc.ready" >"$out/vmc.json" &
vmc_pid=$!
for _ in $(seq 100); do [ -f "$out/vmc.ready" ] && break; sleep 0.1; done

start_app "$out/app.log" "${args[@]}"

# A second app on the same server is refused, saying why (the JACK client name is taken).
if second="$("$app" --no-gui --no-osc 2>&1)"; then
  echo "a second pneuma-app started on the same JACK server" >&2; exit 1
fi
case "$second" in
  *"already has a client named"*) echo "a second app is refused: $second" ;;
  *) echo "a second pneuma-app failed without saying why: $second" >&2; exit 1 ;;
esac

"$py" "$here/jack_play.py" --play "$voice" --record "$out/output.wav" --tail-s 0.5
echo "recorded output: $out/output.wav"
python3 "$here/check_live.py" breaths --input "$voice" --output "$out/output.wav" --min-breaths 2

if [ "$mode" = gui ]; then
  import -window root "$out/editor.png"
  convert "$out/editor.png" -depth 8 "ppm:$out/editor.ppm"
  echo "screenshot: $out/editor.png"
  python3 "$here/check_live.py" screenshot --ppm "$out/editor.ppm" --min-breath-pixels 300
fi

if ! wait "$vmc_pid"; then
  echo "VMC receiver refused the app's output: $(cat "$out/vmc.json")" >&2
  exit 1
fi
echo "VMC received: $(cat "$out/vmc.json")"
# The app's CPU time (all threads) since it started, for the editor's cost: gui minus headless.
ticks="$(getconf CLK_TCK)"
cpu_s="$(awk -v t="$ticks" '{printf "%.2f", ($14 + $15) / t}' "/proc/$app_pid/stat")"
echo "pneuma-app CPU ($mode): $cpu_s s over the run (25.3 s of voice plus start-up)"

# Quitting: Ctrl+C 4 s into the voice, while the avatar moves: the app ends within 5 s with
# status 0, and its last VMC frame is the rest pose (app/tests/last_head.py: a moving head
# before it). The app runs as a script's background job, which starts with SIGINT ignored:
# nice-plug's wrapper takes it anyway, as a terminal's Ctrl+C reaches it.
listen_last --require-motion
"$py" "$here/jack_play.py" --play "$voice" --record "$out/quit-output.wav" --tail-s 0 \
  >/dev/null 2>&1 &
play_pid=$!
pids+=("$play_pid")
sleep 4
quit_app INT "$app_pid" "$out/app.log"
kill "$play_pid" 2>/dev/null || true
rest_received "Ctrl+C ($mode)"
how="the wrapper stopped"
grep -q "did not stop within" "$out/app.log" && how="the backend hung; the app ended itself"
echo "Ctrl+C ($mode) mid-voice: pneuma-app quit in $quit_s s with status 0 ($how); last VMC head: the rest pose, after a moving one"

if [ "$mode" = headless ]; then
  wait_ports_gone
  # SIGTERM while the backend cannot stop (the JACK server stopped answering: SIGSTOP): the app
  # ends itself after its grace period, saying so, and sends the rest pose.
  start_app "$out/app-term.log" "${args[@]}"
  kill -STOP "${pids[0]}"
  # Frames already on their way arrive first; from here on only the app's own can.
  sleep 0.5
  listen_last
  quit_app TERM "$app_pid" "$out/app-term.log"
  kill -CONT "${pids[0]}"
  rest_received "SIGTERM with the JACK server not answering"
  grep -q "did not stop within" "$out/app-term.log" || {
    echo "SIGTERM with a stuck backend: the app did not say why it ended; its log:" >&2
    cat "$out/app-term.log" >&2; exit 1; }
  echo "SIGTERM with the JACK server not answering: pneuma-app ended itself in $quit_s s with status 0; last VMC head: the rest pose"
  wait_ports_gone

  start_app "$out/app-stop.log" --no-gui --no-osc
  # The JACK server stops under the app: it must say so and exit with status 1, not hang.
  kill -TERM "${pids[0]}"
  for _ in $(seq 100); do kill -0 "$app_pid" 2>/dev/null || break; sleep 0.1; done
  if kill -0 "$app_pid" 2>/dev/null; then
    echo "pneuma-app hangs on after the JACK server stopped" >&2; exit 1
  fi
  set +e; wait "$app_pid"; app_rc=$?; set -e
  grep -q "the JACK server stopped" "$out/app-stop.log" && [ "$app_rc" = 1 ] || {
    echo "pneuma-app exited $app_rc after the JACK server stopped; its log:" >&2
    cat "$out/app-stop.log" >&2; exit 1; }
  echo "the JACK server stopped: pneuma-app said so and exited 1"
fi
echo "live test ($mode) passed"
