"""The matrix's process pool: forked only for a map of two tasks or more, results in order."""

from __future__ import annotations

import multiprocessing
import os

import pytest

from geomcheck.selfcollision.workers import Workers, shared


def _pid_and_state(item: int) -> tuple[int, int, int]:
    return item, os.getpid(), shared()["offset"] + item


@pytest.mark.skipif("fork" not in multiprocessing.get_all_start_methods(), reason="no fork on this platform")
def test_the_pool_is_forked_on_the_first_map_of_two_tasks() -> None:
    with Workers({"offset": 100}, 2) as workers:
        assert workers.map(_pid_and_state, []) == []
        assert workers.map(_pid_and_state, [7]) == [(7, os.getpid(), 107)]  # one task: in this process
        assert not workers.parallel
        results = workers.map(_pid_and_state, range(6))
        assert workers.parallel
        assert [r[0] for r in results] == list(range(6)) and [r[2] for r in results] == list(range(100, 106))
        assert all(pid != os.getpid() for _, pid, _ in results)
    assert not workers.parallel and shared() is None


def test_one_worker_never_forks() -> None:
    with Workers({"offset": 1}, 1) as workers:
        results = workers.map(_pid_and_state, range(4))
        assert not workers.parallel
    assert results == [(i, os.getpid(), 1 + i) for i in range(4)]
