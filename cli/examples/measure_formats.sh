#!/usr/bin/env bash
# Decode and render speed and peak memory per input format, on a generated episode:
#   cli/examples/measure_formats.sh [SECONDS [RATE CHANNELS]]     (default 600 s, 48000 Hz, 2 ch)
#   FORMATS="wav ulaw midi" cli/examples/measure_formats.sh 3600  (only these rows)
# Needs ffmpeg and /usr/bin/time, and the release builds of `pneuma`, the `episode` example
# (pneuma-cli) and the `decode_speed` example (pneuma-io):
#   cargo build --release -p pneuma-cli --bin pneuma --example episode \
#     -p pneuma-io --example decode_speed
# Prints one row per format: decode speed (multiples of real time, pneuma-io alone), render
# wall time with the plot, render speed and the render's peak resident memory; then the same
# WAV read through symphonia's WAV reader, the measure behind pneuma-io's choice of its own.
set -euo pipefail
cd "$(dirname "$0")/../.."
secs=${1:-600}
rate=${2:-48000}
ch=${3:-2}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
bin=target/release
"$bin/examples/episode" "$dir/ep.wav" "$secs" "$rate" "$ch"
enc() { ffmpeg -hide_banner -loglevel error -y -i "$dir/ep.wav" "$@"; }
formats=${FORMATS:-wav flac aiff caf mp3 m4a ogg ulaw alaw midi}
mkdir -p "$dir/ulaw" "$dir/alaw"
for f in $formats; do # the encodings the chosen rows need
  case $f in
    ulaw) enc -c:a pcm_mulaw "$dir/ulaw/ep.wav" ;;
    alaw) enc -c:a pcm_alaw "$dir/alaw/ep.wav" ;;
    flac) enc -c:a flac "$dir/ep.flac" ;;
    aiff) enc -c:a pcm_s16be "$dir/ep.aiff" ;;
    caf) enc -c:a pcm_s16le "$dir/ep.caf" ;;
    mp3) enc -c:a libmp3lame -b:a 128k "$dir/ep.mp3" ;;
    m4a) enc -c:a aac -b:a 128k "$dir/ep.m4a" ;;
    ogg) enc -c:a libvorbis -q:a 5 "$dir/ep.ogg" ;;
  esac
done
echo "episode: $secs s, $rate Hz, $ch ch (16-bit source; lossy at 128 kb/s or Vorbis q5)"
printf '%-5s %12s %10s %10s %10s %9s\n' format decode_x render_s render_x peak_MB output
row() { # format file [render flags]
  local f=$1 file=$2
  shift 2
  local dec
  dec=$("$bin/examples/decode_speed" "$file" | sed -E 's/.*= ([0-9]+)x real time/\1/')
  /usr/bin/time -f '%e %M' -o "$dir/t" "$bin/pneuma" render "$file" -o "$dir/out_$f" --quiet \
    --any-sound "$@"
  local wall kb out
  read -r wall kb < "$dir/t"
  out=$(cd "$dir/out_$f" && ls ep.wav ep.flac ep.aiff 2>/dev/null | head -1 || true)
  awk -v f="$f" -v d="$dec" -v w="$wall" -v kb="$kb" -v s="$secs" -v o="$out" \
    'BEGIN { printf "%-5s %11sx %10.2f %9.0fx %10.1f %9s\n", f, d, w, s / w, kb / 1024, o }'
}
# ulaw/alaw: the same episode as 8-bit G.711 WAV; midi: the WAV rendered with --midi as well.
for f in $formats; do
  case $f in
    ulaw | alaw) row "$f" "$dir/$f/ep.wav" ;;
    midi) row "$f" "$dir/ep.wav" --midi ;;
    *) row "$f" "$dir/ep.$f" ;;
  esac
done
echo "WAV decision (pneuma-io's own reader vs symphonia's WAV reader, decode only):"
for mode in own symphonia; do
  flag=()
  [ "$mode" = symphonia ] && flag=(--symphonia-wav)
  /usr/bin/time -f '%e %M' -o "$dir/t" "$bin/examples/decode_speed" "${flag[@]}" "$dir/ep.wav" \
    > "$dir/d"
  read -r wall kb < "$dir/t"
  printf '  %-9s %s, peak %.1f MB\n' "$mode" "$(sed -E 's/.*= //' "$dir/d")" \
    "$(awk -v kb="$kb" 'BEGIN { print kb / 1024 }')"
done
