#!/bin/bash -eu
# Builds every cargo-fuzz target of tetwalk into $OUT, with its seed corpus, for ClusterFuzzLite (or
# OSS-Fuzz). The targets hold tetwalk's own methods (`exact`, `certified`: TETWALK_FUZZ_METHOD=ours
# compiled in as the default), which must never fail, so a crash is a bug; the published methods'
# known failures are hunted with fuzz/campaign.sh. CI runs this script with SRC and OUT set.
cd "$SRC/tetwalk"
export TETWALK_FUZZ_DEFAULT=ours
cargo fuzz build -O
triple=$(rustc -vV | sed -n 's/^host: //p')
for target in $(cargo fuzz list); do
    cp "fuzz/target/$triple/release/$target" "$OUT/"
    if [ -d "corpora/$target" ]; then
        (cd "corpora/$target" && zip -q -r "$OUT/${target}_seed_corpus.zip" .)
    fi
done
