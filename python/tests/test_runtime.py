"""The runtime side: the GIL released while rendering, Ctrl-C, progress,
cancel from another thread, snapshots under concurrent edits, images handed
over without a copy, memory flat over many renders."""
import signal
import threading

import numpy as np
import pytest

import glint


def rss_bytes():
    with open("/proc/self/statm") as f:
        import os
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_the_image_buffer_is_the_renderers(small):
    r = glint.render(small, passes=["depth", "diffuse"])
    img = r.image
    # The array wraps the renderer's vector (kept alive by a capsule): its
    # data pointer is the one the C++ render returned, and numpy owns nothing.
    assert img.__array_interface__["data"][0] == r._buffer_address
    assert not img.flags.owndata and type(img.base).__name__ == "PyCapsule"
    assert img.dtype == np.float32 and img.shape == (30, 40, 3) and img.flags.c_contiguous
    # depth is a strided (H, W) view of its 3-channel buffer, not a copy
    assert r.passes["depth"].strides == (40 * 12, 12) and not r.passes["depth"].flags.owndata
    del r
    assert img.sum() > 0  # the array keeps its buffer alive alone


def test_the_gil_is_released_while_rendering(small):
    """A helper thread's Python code runs during the render: it waits until the
    render is in its pixel loop, then cancels it. The render (long enough to
    take minutes) comes back incomplete, which only that thread can cause."""
    token = glint.CancelToken()
    ran = threading.Event()

    def helper():
        while not token.running:
            pass
        ran.set()
        token.cancel()

    t = threading.Thread(target=helper)
    t.start()
    r = glint.render(small, width=2000, height=2000, spp=256, cancel=token)
    t.join()
    assert ran.is_set()
    assert r.stats["complete"] is False
    assert r.image.shape == (2000, 2000, 3)


def test_ctrl_c_stops_the_render_and_raises(small):
    calls = []

    def progress(fraction):
        calls.append(fraction)
        if len(calls) == 1:
            signal.raise_signal(signal.SIGINT)  # what Ctrl-C does

    with pytest.raises(KeyboardInterrupt):
        glint.render(small, width=2000, height=2000, spp=256, progress=progress)
    assert calls[0] == 0.0 and len(calls) <= 2  # it stopped at once, not after minutes
    assert glint.render(small).stats["complete"]  # and the scene renders again


def test_progress_runs_on_the_calling_thread_and_its_exception_stops_the_render(small):
    seen = []
    glint.render(small, progress=lambda f: seen.append((f, threading.get_ident())))
    assert seen[0][0] == 0.0 and seen[-1][0] == 1.0
    assert {t for _, t in seen} == {threading.get_ident()}

    def fail(fraction):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        glint.render(small, width=2000, height=2000, spp=256, progress=fail)


def test_a_render_uses_a_snapshot_while_another_thread_edits(small):
    """Another thread edits the scene after the render has started (before any
    pixel: progress(0) waits for the edit): the image is that of the scene as
    it was, and the edit is kept for the next render."""
    before = glint.render(small.copy()).image
    token = glint.CancelToken()
    edited = threading.Event()

    def editor():
        while not token.running:
            pass
        small.materials["red"].diffuse = (0.1, 0.9, 0.1)
        small.lights[0].position = (3, 3, 3)
        edited.set()

    t = threading.Thread(target=editor)
    t.start()
    r = glint.render(small, cancel=token, progress=lambda f: edited.wait() if f == 0.0 else None)
    t.join()
    assert np.array_equal(r.image, before)
    assert small.materials["red"].diffuse == (0.1, 0.9, 0.1)
    assert not np.array_equal(glint.render(small).image, before)


def test_two_hundred_renders_keep_memory_flat(small):
    rss = {}
    for i in range(1, 201):
        r = glint.render(small, passes=["diffuse", "depth"])
        assert r.image.shape == (30, 40, 3)
        if i % 40 == 0:
            small.materials["red"].shininess = 10 + i  # edits along the way
        if i in (20, 200):
            rss[i] = rss_bytes()
    assert rss[200] - rss[20] < 5 * 2**20, rss


def test_save_writes_what_the_cli_writes(small, tmp_path):
    r = glint.render(small)
    r.save(tmp_path / "a.pfm")
    assert np.array_equal(glint.read_image(tmp_path / "a.pfm"), r.image)
    r.save(tmp_path / "a.png", exposure=1, tonemap="aces")
    png = r._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError):
        r.save(tmp_path / "b.png", tonemap="filmic")


def test_help_and_version_read_well():
    assert glint.__version__.count(".") == 2
    assert "GIL" in glint.render.__doc__ and "passes" in glint.render.__doc__
    assert issubclass(glint.SceneError, ValueError)
    assert "path" in glint.SceneError.__doc__
