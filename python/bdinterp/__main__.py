"""``python3 -m bdinterp ...``: same as the ``bdinterp`` command."""

import sys

from bdinterp.cli import main

sys.exit(main())
