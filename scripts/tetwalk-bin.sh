# Sourced by every script that runs tetwalk (never run alone): sets `tetwalk` to the program to run.
# That is $TETWALK when set (a binary anywhere: installed, copied, another build), else the release
# build in cargo's target directory for this checkout, as `cargo metadata` reports it (so
# CARGO_TARGET_DIR and .cargo/config.toml's build.target-dir are honoured). With TETWALK_BUILD=1 in
# the caller, that build is made or brought up to date first.
tetwalk_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ -n "${TETWALK:-}" ]; then
    tetwalk=$TETWALK
else
    if [ "${TETWALK_BUILD:-0}" = 1 ]; then
        cargo build --release --quiet --manifest-path "$tetwalk_root/Cargo.toml" --bin tetwalk
    fi
    tetwalk_target=$(cargo metadata --format-version 1 --no-deps --manifest-path "$tetwalk_root/Cargo.toml" 2>/dev/null |
        sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
    tetwalk=${tetwalk_target:-${CARGO_TARGET_DIR:-$tetwalk_root/target}}/release/tetwalk
fi
if ! [ -x "$tetwalk" ]; then
    echo "no tetwalk program at $tetwalk: build it (cargo build --release) or set TETWALK to one" >&2
    exit 2
fi
