# test_threads.py — the GIL is released while rendering, and Ctrl-C (SIGINT) stops a render at once and raises
# KeyboardInterrupt, leaving the interpreter usable.
import os
import subprocess
import sys
import textwrap
import threading
import time


import glint
from conftest import scene_path

LONG = dict(width=64, height=64, spp=1000000, threads=2)  # hours: only a stop ends it


def test_render_on_a_thread_while_the_main_thread_runs_python():
    scene = glint.load(scene_path("cornell-box.json"))
    result = {}

    def work():
        result["image"] = scene.render(width=48, height=48, spp=48, threads=1)

    t = threading.Thread(target=work)
    t.start()
    ticks = 0
    while t.is_alive():
        ticks += 1  # pure Python: runs only while the render does not hold the GIL
    t.join()
    assert result["image"].shape == (48, 48, 3)
    assert ticks > 10000, ticks


def test_a_scene_being_rendered_refuses_a_second_render():
    scene = glint.load(scene_path("cornell-box.json"))
    stop = threading.Event()
    errors = []

    def progress(_):
        if stop.is_set():
            raise KeyboardInterrupt

    def work():
        try:
            scene.render(progress=progress, **LONG)
        except KeyboardInterrupt:
            pass
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    t = threading.Thread(target=work)
    t.start()
    time.sleep(0.3)
    try:
        scene.render(width=4, height=4)
        assert False, "a second render of a busy scene ran"
    except glint.Error as e:
        assert str(e) == "render: the scene is being rendered on another thread"
    try:
        scene.add_light(type="ambient", intensity=1)
        assert False, "a busy scene was changed"
    except glint.Error as e:
        assert str(e) == "add_light: the scene is being rendered on another thread"
    stop.set()
    t.join(20)
    assert not t.is_alive() and not errors
    # two scenes render at once on two threads, each as it would alone
    a, b = glint.load(scene_path("cornell-box.json")), glint.load(scene_path("cornell-box.json"))
    images = {}
    threads = [threading.Thread(target=lambda k=k, s=s: images.__setitem__(k, s.render(width=24, height=24, spp=4,
                                                                                        threads=1)))
               for k, s in (("a", a), ("b", b))]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    alone = glint.load(scene_path("cornell-box.json")).render(width=24, height=24, spp=4, threads=1)
    assert images["a"].tobytes() == alone.tobytes() == images["b"].tobytes()


# Run in a child interpreter: the signal goes to that process alone.
CHILD = textwrap.dedent("""
    import os, signal, sys, threading, time
    import glint
    scene = glint.load(sys.argv[1])
    sent = []
    def interrupt():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)
    threading.Timer(0.5, interrupt).start()
    try:
        scene.render(width=64, height=64, spp=1000000, threads=2)
        print("finished?!")
    except KeyboardInterrupt:
        print("KeyboardInterrupt after %.3f s" % (time.monotonic() - sent[0]))
    # the interpreter and the scene are usable: render again, to the end
    image = scene.render(width=8, height=8, spp=2)
    print("again", image.shape)
""")


def run_child(extra_env=None):
    env = dict(os.environ, **(extra_env or {}))
    return subprocess.run([sys.executable, "-c", CHILD, scene_path("cornell-box.json")], env=env,
                          capture_output=True, text=True, timeout=60)


def test_ctrl_c_stops_the_render_and_raises_keyboard_interrupt():
    r = run_child()
    assert r.returncode == 0, r.stderr
    lines = r.stdout.split("\n")
    assert lines[0].startswith("KeyboardInterrupt after"), r.stdout + r.stderr
    assert float(lines[0].split()[2]) < 1.0  # within one pass: the token stops it before the next sample
    assert lines[1] == "again (8, 8, 3)"


def test_ctrl_c_from_outside_and_a_handler_of_the_programs_own():
    child = textwrap.dedent("""
        import signal, sys
        import glint
        class Stopped(Exception):
            pass
        def handler(signum, frame):
            raise Stopped("signal %d" % signum)
        signal.signal(signal.SIGINT, handler)
        scene = glint.load(sys.argv[1])
        print("rendering", flush=True)
        try:
            scene.render(width=64, height=64, spp=1000000, threads=2)
        except Stopped as e:
            print("stopped:", e, flush=True)
    """)
    p = subprocess.Popen([sys.executable, "-c", child, scene_path("cornell-box.json")], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    assert p.stdout.readline() == "rendering\n"
    time.sleep(0.3)
    p.send_signal(2)
    out, err = p.communicate(timeout=30)
    assert p.returncode == 0, err
    assert out == "stopped: signal 2\n"
