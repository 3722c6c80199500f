import sys

from metamaterial_wb.cli import main

sys.exit(main())
