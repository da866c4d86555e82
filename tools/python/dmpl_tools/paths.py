"""Where things are: the source tree, the build tree, the executables."""
import os
import shutil
from pathlib import Path

ROOT = Path(os.environ.get("DMPL_ROOT", Path(__file__).resolve().parents[3]))
BUILD = Path(os.environ.get("DMPL_BUILD_DIR", ROOT / "build"))
BIN = BUILD / "bin"
# Where runs, sweeps and the demo go by default: the source tree's out/, or (an installed dmpl,
# whose share/ may be read-only) what its wrapper sets, ./out.
OUT = Path(os.environ.get("DMPL_OUT", ROOT / "out"))


def executable(name: str) -> str:
    """Resolves an executable: build/bin first, then PATH. Raises with a clear message."""
    candidate = BIN / name
    if candidate.is_file() and os.access(candidate, os.X_OK):
        return str(candidate)
    found = shutil.which(name)
    if found:
        return found
    raise FileNotFoundError(f"executable '{name}' not found in {BIN} or on PATH (run tools/dmpl build)")
