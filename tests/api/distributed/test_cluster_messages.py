"""Any message on the broker's queue is run, or logged and put on the dead-letter queue: never
requeued, never the end of a worker (two real `geomcheck worker`s on Redis and on RabbitMQ,
with PostgreSQL); a normal check completes after them all."""

from __future__ import annotations

import base64
import json
import re
import secrets
import time
from pathlib import Path
from typing import Any

import httpx
import pytest
from apitools import TWO_LINKS, unique_prefix
from clustertools import Cluster, cluster, database_url, rabbitmq_url, redis_url

from api.distributed.deadletters import MAX_DEAD_LETTERS, dead_letter_queue
from api.store import Store

pytestmark = pytest.mark.long

GOOD_BODY = b'[["nosuchcheck"], {}, {"callbacks": null, "errbacks": null, "chain": null, "chord": null}]'


def headers(**changed: Any) -> dict[str, Any]:
    """Celery's protocol 2 headers of a run_check message, with ``changed``."""
    found: dict[str, Any] = {
        "lang": "py",
        "task": "geomcheck.run_check",
        "id": "0123",
        "root_id": "0123",
        "parent_id": None,
        "group": None,
        "argsrepr": "",
        "kwargsrepr": "",
    }
    found.update(changed)
    return {k: v for k, v in found.items() if v != "-"}


# sound envelopes around contents no worker can run: (body, headers, content type)
MALFORMED = {
    "body not JSON": (b"%%%", headers(), "application/json"),
    "unknown task": (GOOD_BODY, headers(task="evil.task"), "application/json"),
    "ETA not a date": (GOOD_BODY, headers(eta="not a date"), "application/json"),
    "expiry not a date": (GOOD_BODY, headers(expires="yesterday"), "application/json"),
    "time limit not a pair": (GOOD_BODY, headers(timelimit="x"), "application/json"),
    "no task id": (GOOD_BODY, headers(id="-"), "application/json"),
    "task id a list": (GOOD_BODY, headers(id=[1]), "application/json"),
    "arguments a mapping": (b'{"a": 1}', headers(), "application/json"),
    "check id a list": (b"[[[1, 2]], {}, {}]", headers(), "application/json"),
    "check id too long": (b'[["' + b"x" * 500 + b'"], {}, {}]', headers(), "application/json"),
    "pickle": (GOOD_BODY, headers(), "application/x-python-serialize"),
}


def redis_envelope(body: bytes, header: dict[str, Any], content_type: str, **properties: Any) -> bytes:
    found = {
        "delivery_tag": secrets.token_hex(8),
        "body_encoding": "base64",
        "delivery_info": {"exchange": "", "routing_key": "q"},
        "priority": 0,
        "delivery_mode": 2,
        **properties,
    }
    envelope = {
        "body": base64.b64encode(body).decode(),
        "content-type": content_type,
        "content-encoding": "utf-8",
        "headers": header,
        "properties": found,
    }
    return json.dumps(envelope).encode()


# Redis only: envelopes kombu itself cannot take apart
REDIS_GARBAGE = {
    "not JSON": b"not json",  # was: Unrecoverable error: JSONDecodeError, the worker exited
    "a JSON list": b"[1, 2]",
    "no delivery tag": b'{"body": "eA==", "properties": {}}',
    "not UTF-8": b"\xff\xfe\x00",
    # was: TypeError in Celery's strategy, the worker exited, the message restored, the next worker killed
    "body not base64": json.dumps(
        {
            "body": "%%%",
            "content-type": "application/json",
            "headers": headers(),
            "properties": {
                "delivery_tag": "t",
                "body_encoding": "base64",
                "delivery_info": {"exchange": "", "routing_key": "q"},
            },
        }
    ).encode(),
    "delivery info without routing key": redis_envelope(
        GOOD_BODY, headers(), "application/json", delivery_info={"exchange": ""}
    ),
    "delivery tag a list": redis_envelope(GOOD_BODY, headers(), "application/json", delivery_tag=[1]),
    "headers a string": redis_envelope(GOOD_BODY, headers(), "application/json").replace(
        b'"headers": {', b'"headers": "x", "h": {'
    ),
    "body a number": redis_envelope(GOOD_BODY, headers(), "application/json").replace(
        b'"body": "', b'"body": 5, "b": "'
    ),
}


def push(nodes: Cluster, broker: str) -> int:
    """Put every malformed message on the checks' queue; how many there are."""
    from kombu import Connection, Exchange, Queue

    queue = nodes.env["GEOMCHECK_QUEUE"]
    with Connection(broker, connect_timeout=5) as conn:
        if broker.startswith("redis"):
            client = conn.default_channel.client
            items = [*REDIS_GARBAGE.values(), *(redis_envelope(*m) for m in MALFORMED.values())]
            for item in items:
                client.lpush(queue, item)
            return len(items)
        producer = conn.Producer()
        declared = Queue(queue, Exchange(""), routing_key=queue, durable=True)
        for body, header, content_type in MALFORMED.values():
            producer.publish(
                body,
                routing_key=queue,
                exchange="",
                serializer=None,
                content_type=content_type,
                content_encoding="utf-8",
                headers=header,
                declare=[declared],
            )
        return len(MALFORMED)


def held(broker: str, name: str) -> int:
    """Messages in the queue ``name`` (0 when it does not exist)."""
    from kombu import Connection

    with Connection(broker, connect_timeout=5) as conn:
        channel = conn.default_channel
        if broker.startswith("redis"):
            return int(channel.client.llen(name))
        try:
            return int(channel.queue_declare(name, passive=True).message_count)
        except conn.channel_errors:
            return 0


def drop(broker: str, name: str) -> None:
    from kombu import Connection

    with Connection(broker, connect_timeout=5) as conn:
        if broker.startswith("redis"):
            conn.default_channel.client.delete(name)
        else:
            conn.default_channel.queue_delete(name)


@pytest.mark.parametrize("broker_of", [redis_url, rabbitmq_url], ids=["redis", "rabbitmq"])
def test_malformed_messages_are_dead_lettered_and_the_workers_go_on(tmp_path: Path, broker_of: Any) -> None:
    database, broker, prefix = database_url(), broker_of(), unique_prefix()
    store = Store(database, prefix)
    dead = ""
    try:
        with cluster(tmp_path, broker, database, prefix) as nodes:
            queue = nodes.env["GEOMCHECK_QUEUE"]
            dead = dead_letter_queue(queue)
            workers = [nodes.start_worker(name) for name in ("w1", "w2")]
            base = nodes.start_api("api1")
            for name in ("w1", "w2"):
                nodes.wait_worker_ready(name)
            sent = push(nodes, broker)
            deadline = time.monotonic() + 60
            while held(broker, dead) < sent and time.monotonic() < deadline:
                time.sleep(0.2)
            logs = nodes.log("w1") + nodes.log("w2")
            assert held(broker, dead) == sent, logs[-4000:]  # every one dead-lettered, none lost in between
            assert held(broker, queue) == 0  # none given back to the checks' queue
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
            logs = nodes.log("w1") + nodes.log("w2")
            assert status == "succeeded", logs[-4000:]
            assert all(worker.poll() is None for worker in workers)  # both still running
            assert "Unrecoverable error" not in logs and "Restoring" not in logs
            assert "Connection to broker lost" not in logs
            assert held(broker, dead) == sent  # the check's message was not one of them
            metrics = httpx.get(f"{base}/metrics", timeout=30).text
            assert re.search(rf"^geomcheck_dead_letters {sent}(\.0)?$", metrics, re.MULTILINE), metrics
            assert sent < MAX_DEAD_LETTERS
    finally:
        if dead:
            drop(broker, dead)
        store.drop_schema()
        store.dispose()
