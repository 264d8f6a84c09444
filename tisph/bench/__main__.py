import sys

from ..errors import ConfigError
from .cli import main

if __name__ == "__main__":  # not again in a worker process of --jobs
    try:
        sys.exit(main())
    except ConfigError as e:  # a bad case file given with --config: the message, not a traceback
        print(f"python -m tisph.bench: {e}", file=sys.stderr)
        sys.exit(2)
