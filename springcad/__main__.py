import sys

from springcad.cli import main

sys.exit(main())
