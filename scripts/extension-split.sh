#!/usr/bin/env bash
# One extension source folder for the bdinterp wheels in WHEELS (any platforms: its manifest lists
# them all, `scripts/build_addon.py --extension-source`), split by Blender into one zip per platform
# (`blender --command extension build --split-platforms`; Blender 4.2+) in OUT, each zip checked
# to hold its platform's wheels only.
#   scripts/extension-split.sh WHEELS OUT BLENDER            a Blender on PATH (the GitHub workflow)
#   scripts/extension-split.sh WHEELS OUT --chroot DIR       Blender of a Debian chroot (needs root)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
wheels=$(realpath "$1") out=$(mkdir -p "$2" && realpath "$2"); shift 2
rm -f "$out"/bdinterp_blender-*.zip
/usr/bin/python3 "$ROOT/scripts/build_addon.py" --extension-source "$wheels" --out "$out"
split=(--command extension build --split-platforms --source-dir SRC/bdinterp_blender --output-dir SRC)
if [ "$1" = --chroot ]; then
  chroot=$2
  mkdir -p "$chroot/splitout"
  unshare -m --propagation private sh -c "mount --bind '$out' '$chroot/splitout' &&
    mount -t proc proc '$chroot/proc' && mount -t tmpfs tmpfs '$chroot/tmp'; rc=0
    chroot '$chroot' env -i HOME=/tmp PATH=/usr/bin:/bin LANG=C.UTF-8 blender ${split[*]//SRC//splitout} || rc=\$?
    umount '$chroot/proc'; exit \$rc"
else
  "$1" "${split[@]//SRC/$out}"
fi
# Each zip: its platform in the name and its manifest, and only the wheels whose tags fit it.
/usr/bin/python3 - "$out" <<'PY'
import glob, os, re, sys, tomllib, zipfile
zips = sorted(glob.glob(os.path.join(sys.argv[1], "bdinterp_blender-*.zip")))
if not zips:
    sys.exit("extension-split: Blender wrote no zip")
tags = {"linux-x64": r"linux(_\d+_\d+)?_x86_64", "windows-x64": r"win_amd64", "macos-arm64": r"macosx_.*_(arm64|universal2)",
        "macos-x64": r"macosx_.*_(x86_64|universal2)", "linux-arm64": r"linux(_\d+_\d+)?_aarch64"}
for z in zips:
    platform = re.search(r"-(linux|windows|macos)[-_](x64|arm64)\.zip$", z)
    if not platform:
        sys.exit("extension-split: %s is not named for one platform" % z)
    name = platform.group(1) + "-" + platform.group(2)
    with zipfile.ZipFile(z) as zf:
        manifest = tomllib.loads(zf.read("blender_manifest.toml").decode())
        wheels = [n for n in zf.namelist() if n.endswith(".whl")]
    assert manifest["platforms"] == [name], (z, manifest["platforms"])
    assert wheels and all(re.search(tags[name] + r"\.whl$", w) for w in wheels), (z, wheels)
    assert sorted("./" + w for w in wheels) == sorted(manifest["wheels"]), (z, manifest["wheels"])
    print("extension-split: %s: %s, %d wheels" % (os.path.basename(z), name, len(wheels)))
PY
