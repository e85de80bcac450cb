"""A malformed message on the broker's queue is rejected and logged; the worker goes on
(a real `geomcheck worker` on Redis and PostgreSQL)."""

from __future__ import annotations

import time
from pathlib import Path

import httpx
import redis
from apitools import TWO_LINKS, unique_prefix
from clustertools import cluster, database_url, redis_url

from api.store import Store

GARBAGE = (
    b"not json",  # was: Unrecoverable error: JSONDecodeError, the worker exited
    b"[1, 2]",
    b'{"body": "eA==", "properties": {}}',  # an envelope without delivery_tag
    b"\xff\xfe\x00",
)
# a sound envelope around a body Celery cannot use: Celery's own rejection (logged, acknowledged)
UNKNOWN = (
    b'{"body": "%%%", "content-type": "application/json", "properties": {"delivery_tag": "t", "body_encoding": '
    b'"base64", "delivery_info": {"exchange": "", "routing_key": "q"}}}'
)


def test_malformed_messages_on_redis_leave_the_worker_running(tmp_path: Path) -> None:
    database, broker, prefix = database_url(), redis_url(), unique_prefix()
    store = Store(database, prefix)
    try:
        with cluster(tmp_path, broker, database, prefix) as nodes:
            worker = nodes.start_worker("w1")
            base = nodes.start_api("api1")
            nodes.wait_worker_ready("w1")
            client = redis.Redis.from_url(broker)
            for item in (*GARBAGE, UNKNOWN):
                client.lpush(nodes.env["GEOMCHECK_QUEUE"], item)
            deadline = time.monotonic() + 30
            while client.llen(nodes.env["GEOMCHECK_QUEUE"]) and time.monotonic() < deadline:
                time.sleep(0.1)
            assert client.llen(nodes.env["GEOMCHECK_QUEUE"]) == 0  # all taken off the queue
            answer = httpx.post(
                f"{base}/v1/checks",
                content=TWO_LINKS,
                params={"wait": "false"},
                headers={"content-type": "application/xml"},
                timeout=30,
            )
            assert answer.status_code == 202, answer.text
            check_id = answer.json()["id"]
            status = ""
            deadline = time.monotonic() + 90
            while time.monotonic() < deadline:
                status = httpx.get(f"{base}/v1/checks/{check_id}", timeout=30).json()["status"]
                if status not in ("queued", "running"):
                    break
                time.sleep(0.3)
            log = nodes.log("w1")
            assert status == "succeeded", log[-3000:]
            assert worker.poll() is None  # still running
            assert "Unrecoverable error" not in log
            assert log.count("rejected a malformed message") == len(GARBAGE), log[-3000:]
            assert "Received and deleted unknown message" in log
    finally:
        store.drop_schema()
        store.dispose()
