"""Run the add-on tests inside real Blender (headless).

    blender --background --factory-startup --python-exit-code 1 \
        --python tests/blender/run_blender_tests.py -- [--zip dist/...-legacy-py311.zip] [pytest args]

Installs the zip (default: the newest dist/bdinterp_blender-*-legacy-*.zip) through Blender's own
add-on installer into a temporary user scripts folder, then runs pytest on
tests/blender/test_*.py in this Blender process and exits with pytest's status.
"""

import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if "--zip" in argv:
        i = argv.index("--zip")
        os.environ["BDI_ADDON_ZIP"] = os.path.abspath(argv[i + 1])
        del argv[i:i + 2]
    # Isolated user folder: the installer writes there, never into the real ~/.config/blender.
    # Blender reads this variable whenever it resolves the user scripts path.
    if not os.environ.get("BDI_KEEP_USER_SCRIPTS"):
        os.environ["BLENDER_USER_SCRIPTS"] = tempfile.mkdtemp(prefix="bdi_blender_user_")
    # Debian's Blender uses the system Python 3.11; pytest comes from python3-pytest.
    for path in ("/usr/lib/python3/dist-packages",):
        if os.path.isdir(path) and path not in sys.path:
            sys.path.append(path)
    import pytest
    paths = [a for a in argv if not a.startswith("-") and os.path.exists(a.split("::")[0])]
    # Own ini file: the project's pytest settings are for tests/python, not for Blender.
    code = pytest.main(["-c", os.path.join(HERE, "pytest.ini"), "--rootdir", HERE,
                        "-p", "no:cacheprovider", *argv] + ([] if paths else [HERE]))
    sys.stdout.flush()
    sys.exit(int(code))


main()
