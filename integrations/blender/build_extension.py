"""Packs the Blender extension: builds the dentbend wheel for this platform (into
<out>/stage/wheels), lists it and its platform in the manifest, and zips the add-on with it.

    python integrations/blender/build_extension.py --out target/blender

Blender installs the zip with Edit > Preferences > Get Extensions > Install from Disk. The
wheel is abi3 (CPython 3.9 and later), so one zip serves every Blender from 4.2 on this
platform; build once per platform (Linux, Windows, macOS) for the others.
"""

import argparse
import pathlib
import re
import shutil
import subprocess
import sys
import zipfile

HERE = pathlib.Path(__file__).resolve().parent
ADDON = HERE / "dentbend_blender"
PACKAGE = HERE.parent / "python"


def build_wheel(wheels):
    """Builds the dentbend wheel into ``wheels`` (emptied first); returns its path."""
    shutil.rmtree(wheels, ignore_errors=True)
    wheels.mkdir(parents=True)
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--wheel-dir", str(wheels), str(PACKAGE)], check=True
    )
    built = sorted(wheels.glob("dentbend-*.whl"))
    if len(built) != 1:
        raise SystemExit(f"expected one dentbend wheel in {wheels}, found {[w.name for w in built]}")
    return built[0]


def platform_of(wheel):
    """Blender's name for the platform a wheel's tag names (the extension installs only there)."""
    tag = wheel.stem.split("-")[-1]
    system = "linux" if "linux" in tag else "windows" if tag.startswith("win") else "macos" if "macosx" in tag else None
    machine = "arm64" if ("aarch64" in tag or "arm64" in tag) else "x64" if ("x86_64" in tag or "amd64" in tag) else None
    if system is None or machine is None:
        raise SystemExit(f"no Blender platform for the wheel tag {tag}")
    return f"{system}-{machine}"


def manifest_with(wheel):
    """The manifest's text with its wheels list naming ``wheel``, and its platform."""
    text = (ADDON / "blender_manifest.toml").read_text()
    listed = f'wheels = ["./wheels/{wheel.name}"]\nplatforms = ["{platform_of(wheel)}"]'
    text, count = re.subn(r"(?m)^wheels = \[.*\]$", listed, text)
    if count != 1:
        raise SystemExit("blender_manifest.toml has no one-line `wheels = [...]` entry")
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=pathlib.Path, default=pathlib.Path("target/blender"))
    args = parser.parse_args()
    stage = args.out / "stage"
    wheel = build_wheel(stage / "wheels")
    version = re.search(r'(?m)^version = "([^"]+)"', manifest_with(wheel)).group(1)
    archive = args.out / f"dentbend-{version}-blender.zip"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as zf:
        for path in sorted(ADDON.glob("*.py")):
            zf.write(path, path.name)
        zf.writestr("blender_manifest.toml", manifest_with(wheel))
        zf.write(wheel, f"wheels/{wheel.name}")
    print(archive)


if __name__ == "__main__":
    main()
