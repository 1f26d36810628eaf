#!/usr/bin/env bash
# Seeds the fuzz corpora: the first 64 KiB of each shared real log (header, definitions
# and the first data: a minimised log) and the
# format strings of the real logs.
set -euo pipefail
cd "$(dirname "$0")"
shared=${ULOG_CORPUS:-../../shared/corpus}
mkdir -p corpus/reader corpus/chunked corpus/columns corpus/grammar corpus/typed corpus/roundtrip
if [ -d "$shared/files" ]; then
    for f in "$shared"/files/*.ulg; do
        name=$(basename "$f" .ulg)
        head -c 65536 "$f" > "corpus/reader/$name"
        head -c 65536 "$f" > "corpus/chunked/$name"
        # columns: three bytes first (threads, then the sample's size: 4 KiB).
        { printf '\000\000\020'; head -c 65536 "$f"; } > "corpus/columns/$name"
        # Format messages ('F'): the text after each header, one seed per log.
        python3 - "$f" "corpus/grammar/$name" <<'PY'
import struct, sys
data = open(sys.argv[1], 'rb').read()
pos, texts = 16, []
while pos + 3 <= len(data) and len(texts) < 64:
    size, t = struct.unpack_from('<HB', data, pos)
    if t == ord('F'):
        texts.append(data[pos + 3:pos + 3 + size])
    if t == ord('A'):
        break
    pos += 3 + size
open(sys.argv[2], 'wb').write(b'\n'.join(texts))
PY
    done
else
    echo "seed: no shared corpus at $shared; the corpora start empty" >&2
fi
