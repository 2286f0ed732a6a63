"""meshcat's viewer script, compressed once per machine (viz/viewer/assets.py: the user's cache, named by the
script's SHA-256): read back the same, recomputed when the cached file is damaged, and no harm when the cache
cannot be written."""
import os

import pytest

from rbcourse.viz.viewer import assets


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    monkeypatch.setenv("RBCOURSE_CACHE_DIR", str(tmp_path / "cache"))
    assets._viewer.cache_clear()
    yield tmp_path / "cache"
    assets._viewer.cache_clear()


def test_the_compressed_script_is_kept_and_read_back_the_same(fresh):
    text, n = assets.viewer_script()
    files = list(fresh.iterdir())
    assert len(files) == 1 and files[0].name.startswith("meshcat-") and files[0].suffix == ".b85"
    assets._viewer.cache_clear()
    calls = []
    real = assets.compress
    try:
        assets.compress = lambda data: calls.append(1) or real(data)
        assert assets.viewer_script() == (text, n)
    finally:
        assets.compress = real
    assert not calls                                            # read back, not compressed again
    assert assets.decompress(text) == assets.VIEWER_JS.read_bytes()


def test_a_damaged_cache_is_recomputed(fresh):
    text, n = assets.viewer_script()
    path = next(fresh.iterdir())
    for damaged in ("", "12\nabc", "not a number\n" + text):
        path.write_text(damaged, encoding="ascii")
        assets._viewer.cache_clear()
        assert assets.viewer_script() == (text, n)


def test_a_cache_that_cannot_be_written_is_not_used(monkeypatch, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    monkeypatch.setenv("RBCOURSE_CACHE_DIR", str(blocker / "cache"))      # under a file: cannot be created
    assets._viewer.cache_clear()
    try:
        text, n = assets.viewer_script()
        assert n == os.path.getsize(assets.VIEWER_JS) and assets.decompress(text) == assets.VIEWER_JS.read_bytes()
    finally:
        assets._viewer.cache_clear()
