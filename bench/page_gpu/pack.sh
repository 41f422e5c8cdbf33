#!/usr/bin/env bash
# Packs what bench/page_gpu/run.sh runs into PARTS parts of at most PART_MB MiB each, in
# .dev/p1 ... .dev/pPARTS (ignored; each carried to the GPU machine by one call, which copies it
# to /tmp/chunks/), with .dev/fonts and .gl for the last call: `PARTS=3 PART_MB=48 bash bench/page_gpu/pack.sh` after
# scripts/build-web.sh and a release build of the CLI. Needs Debian's chromium package.
set -eu
PARTS=${PARTS:-3} PART_MB=${PART_MB:-48}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
S=$(mktemp -d)
C=/usr/lib/chromium
mkdir -p $S/chromium/lib $S/chromium/locales
cp $C/icudtl.dat $C/resources.pak $C/chrome_100_percent.pak $C/snapshot_blob.bin $C/v8_context_snapshot.bin \
  $C/libEGL.so $C/libGLESv2.so $C/libvulkan.so.1 $C/chrome_crashpad_handler $S/chromium/
cp $C/locales/en-US.pak $S/chromium/locales/
# The shared libraries the binary needs, under the names it asks for, less glibc's own (the
# GPU machine's is newer), and NSS's modules, which it loads by name at run time.
ldd $C/chromium | awk '$3 ~ /^\// {print $1, $3}' | grep -v -E '^(libc|libm|libdl|libpthread|librt)\.so' |
  while read -r name path; do cp -L "$path" $S/chromium/lib/$name; done
for f in libsoftokn3.so libfreebl3.so libfreeblpriv3.so libnssckbi.so libnssdbm3.so; do
  cp -L /usr/lib/x86_64-linux-gnu/$f $S/chromium/lib/
done
tar cf - -C $S chromium | xz -T0 -9 > $S/chromium_rest.tar.xz
rm -rf $S/chromium
xz -T0 -9 --x86 --lzma2=preset=9,dict=64MiB -c $C/chromium > $S/chromium.xz
objcopy --strip-all "${MESHFLOW:-${CARGO_TARGET_DIR:-$HOME/.cache/meshflow/target}/release/meshflow}" $S/meshflow
xz -T0 -9 $S/meshflow
tar cf - -C $ROOT/web pkg | xz -T0 -9 > $S/pkg.tar.xz
python3 -m pip download -q --no-deps websocket-client==1.9.2 -d $S
cp $ROOT/tests/fixtures/points/stone_lantern_2048.ply $S/
rm -rf $ROOT/.dev/p* && mkdir -p $ROOT/.dev
P=$(mktemp -d)
tar cf - -C $S . | split -b ${PART_MB}M -a 1 - $P/part.
ls $P/part.* | awk -v r=$ROOT '{printf "mkdir -p %s/.dev/p%d && mv %s %s/.dev/p%d/\n", r, NR, $0, r, NR}' | sh
rm -rf $S $P
[ "$(ls -d $ROOT/.dev/p* | wc -l)" -le "$PARTS" ] || { echo "more than $PARTS parts: raise PART_MB" >&2; exit 1; }
# A font for Chromium (the GPU machine has none), and the Vulkan loader and GLVND that NVIDIA's
# Vulkan driver needs, as the device tool's notes give them.
mkdir -p $ROOT/.dev/fonts $ROOT/.gl /tmp/amd64/partial
cp /usr/share/fonts/truetype/dejavu/DejaVuSans.ttf $ROOT/.dev/fonts/
o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
apt-get $o update > /dev/null && (cd $ROOT/.gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
du -b $ROOT/.dev/p*/* $ROOT/.dev/fonts $ROOT/.gl
