# --help documents every subcommand; usage errors exit 2.
source "$(dirname "$0")/lib.bash"
expect 0 "top-level help" -- "$FOVREF" --help
for word in scene render modes golden "scene info" "scene export" "scene list" "golden verify" \
            "golden update" "golden export" "golden list" "Exit codes"; do
  contains "$word" "top-level help"
done
expect 0 "golden help" -- "$FOVREF" golden --help
contains "verify" "golden help"
contains "export" "golden help"
expect 0 "render help" -- "$FOVREF" render --help
contains "--dump" "render help"
expect 0 "version" -- "$FOVREF" --version
contains "fovref" "version"
expect 2 "no subcommand" -- "$FOVREF"
expect 2 "unknown subcommand" -- "$FOVREF" paint
expect 2 "malformed number" -- "$FOVREF" render --mode rng --width abc --out "$TMP/x"
expect 2 "missing positional" -- "$FOVREF" scene info
expect 0 "modes" -- "$FOVREF" modes
contains "splat" "modes"
contains "camera-rays" "modes"
finish
