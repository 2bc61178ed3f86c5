#!/usr/bin/env bash
# The quality guard (scripts/quality.py): scores the real and synthetic data the project has and
# compares every figure with quality/floors.txt ($QUALITY_FLOORS to read another file). One line
# per figure, "NAME VALUE BOUND ok|FAIL"; exit 1 when any fails. Run after the build
# (bash scripts/build.sh); about 20 s on two cores. docs/quality.md says what each figure is.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH  # Debian's python3 (numpy, scipy)
exec python3 "$(cd "$(dirname "$0")" && pwd)/quality.py" "$@"
