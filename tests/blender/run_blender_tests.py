"""Run the add-on tests inside real Blender (headless).

    blender --background --factory-startup --python-exit-code 1 \
        --python tests/blender/run_blender_tests.py -- [--zip LEGACY.zip | --extension EXT.zip] [pytest args]

--zip (default: the newest dist/bdinterp_blender-*-legacy-*.zip): the tests install it through
Blender's own add-on installer into a temporary user scripts folder (Blender 3.4-4.1).
--extension (Blender 4.2+): `blender --command extension validate` must pass, then
`blender --command extension install-file -r user_default` installs it (and the wheel for this
Python) into a temporary user folder, and a fresh Blender that sees that folder runs the tests.
pytest runs on tests/blender/test_*.py in the Blender process; the exit status is pytest's.
"""

import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
# Where a Blender 4.2+ keeps user add-ons, extensions and preferences (one temporary root here).
USER_DIRS = {"BLENDER_USER_SCRIPTS": "scripts", "BLENDER_USER_EXTENSIONS": "extensions",
             "BLENDER_USER_CONFIG": "config"}


def take(argv, flag):
    """Remove `flag VALUE` from argv; return the absolute VALUE or None."""
    if flag not in argv:
        return None
    i = argv.index(flag)
    value = os.path.abspath(argv[i + 1])
    del argv[i:i + 2]
    return value


def blender(*args, env=None):
    import bpy
    return subprocess.run([bpy.app.binary_path, "--background", "--factory-startup", *args],
                          env=env).returncode


def install_extension_and_rerun(zip_path, argv):
    """Validate and install the extension zip with Blender's command line, then run the tests in
    a new Blender (extensions are found at start-up); returns its exit status."""
    root = tempfile.mkdtemp(prefix="bdi_blender_user_")
    env = dict(os.environ, BDI_EXTENSION_ZIP=zip_path,
               **{var: os.path.join(root, sub) for var, sub in USER_DIRS.items()})
    for args in (("validate", zip_path), ("install-file", "-r", "user_default", zip_path)):
        code = blender("--command", "extension", *args, env=env)
        if code:
            print("run_blender_tests: `extension %s` failed (%d)" % (args[0], code))
            return code or 1
    return blender("--python-exit-code", "1", "--python", os.path.abspath(__file__), "--", *argv,
                   env=env)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    legacy = take(argv, "--zip")
    if legacy:
        os.environ["BDI_ADDON_ZIP"] = legacy
    extension = take(argv, "--extension")
    if extension:
        sys.exit(install_extension_and_rerun(extension, argv))
    # Isolated user folder: the installer writes there, never into the real ~/.config/blender.
    # Blender reads this variable whenever it resolves the user scripts path.
    if not os.environ.get("BDI_KEEP_USER_SCRIPTS") and not os.environ.get("BDI_EXTENSION_ZIP"):
        os.environ["BLENDER_USER_SCRIPTS"] = tempfile.mkdtemp(prefix="bdi_blender_user_")
    # pytest: Debian's python3-pytest (Blender 3.4 embeds the system Python 3.11), or files
    # unpacked from Debian's packages (BDI_PYTEST_PATH; the Blender 4.3 chroot has no pytest).
    for path in (os.environ.get("BDI_PYTEST_PATH", ""), "/usr/lib/python3/dist-packages"):
        if path and os.path.isdir(path) and path not in sys.path:
            sys.path.append(path)
    import pytest
    paths = [a for a in argv if not a.startswith("-") and os.path.exists(a.split("::")[0])]
    # Own ini file: the project's pytest settings are for tests/python, not for Blender.
    code = pytest.main(["-c", os.path.join(HERE, "pytest.ini"), "--rootdir", HERE,
                        "-p", "no:cacheprovider", *argv] + ([] if paths else [HERE]))
    sys.stdout.flush()
    sys.exit(int(code))


main()
