"""`python3 -m dbtools.track`: the tracking driver (driver.py; `./run track`)."""
import sys

from .driver import main

sys.exit(main())
