#!/usr/bin/env bash
# make_voice.sh - regenerate assets/examples/voice.wav from transcript.txt.
#
# Each phrase in transcript.txt is synthesised separately with festival's
# text2wave and the CMU ARCTIC "slt" HTS voice (voice_cmu_us_slt_arctic_hts),
# its leading/trailing silence is trimmed with sox, it is resampled to the
# output rate, and the phrases are concatenated with sample-exact digital
# silence of the planned length. Finally the whole file is peak-normalised.
#
# TTS output contains no breath sounds, and the pauses are pure digital
# silence, so the result is a breath-free reference recording.
#
# Requirements (Debian/Ubuntu):
#   sudo apt-get install festival festvox-us-slt-hts sox
#
# Usage: ./make_voice.sh            (writes voice.wav next to this script)
#        ./make_voice.sh out.wav    (writes to another path)
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
TRANSCRIPT="$HERE/transcript.txt"
OUT="${1:-$HERE/voice.wav}"

VOICE="voice_cmu_us_slt_arctic_hts"
RATE=16000          # output sample rate (Hz); keeps the folder under 1 MB
LEAD_IN_MS=300      # digital silence before the first phrase
PEAK_DB=-3          # peak normalisation target (dBFS)
# Trim threshold: anything below 0.1 % of full scale (about -60 dBFS) for the
# whole run at the start/end of a phrase counts as silence. HTS output has a
# vocoder noise floor around -66 dBFS, so this removes it without eating soft
# onsets/offsets.
TRIM_ARGS=(silence 1 0.01 0.1% reverse silence 1 0.01 0.1% reverse)

# --- dependency check -------------------------------------------------------
missing=()
command -v text2wave >/dev/null 2>&1 || missing+=("festival")
command -v sox       >/dev/null 2>&1 || missing+=("sox")
if ((${#missing[@]})); then
    echo "error: missing tools from Debian package(s): ${missing[*]}" >&2
    echo "install with: sudo apt-get install festival festvox-us-slt-hts sox" >&2
    exit 1
fi
if ! echo "(voice_cmu_us_slt_arctic_hts) (print 'ok)" \
        | festival --pipe 2>/dev/null | grep -q ok; then
    echo "error: festival voice $VOICE not available" >&2
    echo "install with: sudo apt-get install festvox-us-slt-hts" >&2
    exit 1
fi
[[ -f "$TRANSCRIPT" ]] || { echo "error: $TRANSCRIPT not found" >&2; exit 1; }

TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

# Sample-exact digital silence of N milliseconds at $RATE.
silence() { # ms outfile
    local samples=$(( $1 * RATE / 1000 ))
    # format options must precede -n, otherwise the null input runs at
    # 48 kHz and gets resampled (and dithered) on the way out
    sox -D -r "$RATE" -c 1 -b 16 -e signed-integer -n "$2" trim 0 "${samples}s"
}

parts=()
silence "$LEAD_IN_MS" "$TMP/lead.wav"
parts+=("$TMP/lead.wav")

i=0
while IFS= read -r line || [[ -n "$line" ]]; do
    [[ -z "${line//[[:space:]]/}" || "$line" == \#* ]] && continue
    text="${line%%$'\t'*}"
    pause="${line##*$'\t'}"
    if [[ "$text" == "$line" || ! "$pause" =~ ^[0-9]+$ ]]; then
        echo "error: bad transcript line (need 'text<TAB>pause_ms'): $line" >&2
        exit 1
    fi
    i=$((i + 1))
    n=$(printf '%02d' "$i")
    printf '%s\n' "$text" > "$TMP/p$n.txt"
    echo "[$n] $text  (+${pause} ms)" >&2
    text2wave -eval "($VOICE)" "$TMP/p$n.txt" -o "$TMP/raw$n.wav"
    # trim silence at native rate, then resample (no dither: keep it clean)
    sox -D "$TMP/raw$n.wav" "$TMP/trim$n.wav" "${TRIM_ARGS[@]}"
    sox -D "$TMP/trim$n.wav" -r "$RATE" -c 1 -b 16 -e signed-integer \
        "$TMP/ph$n.wav" rate -v
    silence "$pause" "$TMP/sil$n.wav"
    parts+=("$TMP/ph$n.wav" "$TMP/sil$n.wav")
done < "$TRANSCRIPT"

((i > 0)) || { echo "error: no phrases in $TRANSCRIPT" >&2; exit 1; }

sox -D "${parts[@]}" "$TMP/concat.wav"
# Peak-normalise; -D keeps the pauses exact digital zero (no dither noise).
sox -D "$TMP/concat.wav" -r "$RATE" -c 1 -b 16 -e signed-integer "$OUT" \
    gain -n "$PEAK_DB"

echo "wrote $OUT" >&2
sox "$OUT" -n stat 2>&1 | grep -E 'Length|Maximum amplitude|Minimum amplitude|RMS +amplitude' >&2
