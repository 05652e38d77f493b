"""The garbage collector is held back while numba compiles and restored afterwards.

:func:`nsdyn._numba_cache.compiling` changes process-wide state (the collector's thresholds,
frozen objects); a library must give it back exactly, also when the compilation raises.
"""

import gc

import pytest

from nsdyn._numba_cache import COMPILE_GC_THRESHOLDS, compiling


@pytest.fixture
def default_gc():
    old = gc.get_threshold()
    gc.unfreeze()
    yield old
    gc.set_threshold(*old)
    gc.unfreeze()


def test_thresholds_and_frozen_objects_restored(default_gc):
    with compiling():
        assert gc.get_threshold() == COMPILE_GC_THRESHOLDS
        assert gc.get_freeze_count() > 0  # the objects alive on entry
    assert gc.get_threshold() == default_gc
    assert gc.get_freeze_count() == 0


def test_restored_when_the_compilation_raises(default_gc):
    with pytest.raises(RuntimeError, match="typing failed"):
        with compiling():
            raise RuntimeError("typing failed")
    assert gc.get_threshold() == default_gc
    assert gc.get_freeze_count() == 0


def test_cyclic_garbage_made_while_compiling_is_collected_afterwards(default_gc):
    """Held back, not switched off: a reference cycle made inside is freed by the next
    collection after the block."""
    import weakref

    class Node:
        pass

    with compiling():
        a, b = Node(), Node()
        a.other, b.other = b, a
        probe = weakref.ref(a)
        del a, b
    gc.collect()
    assert probe() is None


def test_a_helper_ends_with_its_objects_out_of_the_collectors_reach(default_gc):
    """A helper process only exits after its target: what its compilation left is frozen
    (:func:`gc.freeze`) so that the interpreter's last collections, which the calling process
    waits for, do not traverse it; the target itself still ran with the thresholds restored
    after it."""
    from nsdyn._numba_cache import helper_main

    assert helper_main(["gc:collect"]) == 0
    assert gc.get_freeze_count() > 0
    assert gc.get_threshold() == default_gc
