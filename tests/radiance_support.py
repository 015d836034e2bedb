"""Radiance's binaries for the tests that compare with it (radiance_typec_test.py,
radiance_render_test.py, radiance_glare_test.py): the pyradiance wheel (scripts/python-requirements.txt) ships them."""
import pathlib

SKIP = 77  # ctest's SKIP_RETURN_CODE for these tests


def radiance_bindir(tool):
    """The folder of pyradiance's Radiance binaries, or None (after printing why the test is skipped)
    when pyradiance is not installed or has no `tool`."""
    try:
        import pyradiance
    except ImportError:
        print("SKIPPED: pyradiance is not installed in this Python environment (scripts/setup_python.sh)")
        return None
    bindir = pathlib.Path(pyradiance.__file__).parent / "bin"
    if not (bindir / tool).exists():
        print(f"SKIPPED: pyradiance has no {tool} in {bindir}")
        return None
    return bindir
