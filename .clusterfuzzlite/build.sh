#!/bin/bash -eu
# Builds every cargo-fuzz target of tetwalk into $OUT, with its seed corpus, for ClusterFuzzLite (or
# OSS-Fuzz). The targets hold tetwalk's own methods (`exact`, `certified`: TETWALK_FUZZ_METHOD=ours
# compiled in as the default), which must never fail, so a crash is a bug; the published methods'
# known failures are hunted with fuzz/campaign.sh. CI runs this script with SRC and OUT set.
cd "$SRC/tetwalk"
export TETWALK_FUZZ_DEFAULT=ours
cargo fuzz build -O
triple=$(rustc -vV | sed -n 's/^host: //p')
# Where cargo put them: fuzz/target, or CARGO_TARGET_DIR (cargo-fuzz builds where cargo would).
target_dir=$(cargo metadata --format-version 1 --no-deps --manifest-path fuzz/Cargo.toml |
    sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p')
for target in $(cargo fuzz list); do
    cp "$target_dir/$triple/release/$target" "$OUT/"
    if [ -d "corpora/$target" ]; then
        (cd "corpora/$target" && zip -q -r "$OUT/${target}_seed_corpus.zip" .)
    fi
done
