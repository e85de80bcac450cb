"""``/metrics``: Prometheus metrics of the whole deployment, read from the database at each scrape.

Every replica answers with the same figures (checks by status, queue depth, the run-time
histogram of finished checks, and in the distributed mode the messages held on the broker's
dead-letter queue), whichever process ran the checks. Counts fall when the
retention deletes old checks; Prometheus treats that as a counter reset.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from prometheus_client import CollectorRegistry, generate_latest
from prometheus_client.core import GaugeMetricFamily, HistogramMetricFamily
from prometheus_client.registry import Collector

from api.store import DURATION_BUCKETS, Store

CONTENT_TYPE = "text/plain; version=0.0.4; charset=utf-8"


class StoreCollector(Collector):
    """Gauges and a histogram computed from the checks table."""

    def __init__(self, store: Store, distributed: bool, dead_letters: Callable[[], int | None] | None = None) -> None:
        self.store = store
        self.distributed = distributed
        self.dead_letters = dead_letters

    def collect(self) -> Iterator[GaugeMetricFamily | HistogramMetricFamily]:
        counts = self.store.counts_by_status()
        by_status = GaugeMetricFamily("geomcheck_checks", "Stored checks by status", labels=["status"])
        for status, count in counts.items():
            by_status.add_metric([status], count)
        yield by_status
        yield GaugeMetricFamily("geomcheck_queue_depth", "Checks queued, waiting for a worker", value=counts["queued"])
        yield GaugeMetricFamily(
            "geomcheck_distributed",
            "1 when checks run on Celery workers, 0 in the embedded service",
            value=int(self.distributed),
        )
        held = self.dead_letters() if self.dead_letters is not None else None
        if held is not None:
            yield GaugeMetricFamily(
                "geomcheck_dead_letters",
                "Messages no worker could run, held on the dead-letter queue (the newest 1000)",
                value=held,
            )
        cumulative, _count, total = self.store.duration_histogram()
        bounds = [*(f"{b:g}" for b in DURATION_BUCKETS), "+Inf"]
        yield HistogramMetricFamily(
            "geomcheck_check_duration_seconds",
            "Run time of finished checks' processes [s]",
            buckets=list(zip(bounds, cumulative, strict=True)),
            sum_value=total,
        )


def render_metrics(store: Store, distributed: bool, dead_letters: Callable[[], int | None] | None = None) -> bytes:
    """The text exposition of :class:`StoreCollector` for ``store`` (``dead_letters``: how many
    messages the broker's dead-letter queue holds, in the distributed mode)."""
    registry = CollectorRegistry(auto_describe=False)
    registry.register(StoreCollector(store, distributed, dead_letters))
    return generate_latest(registry)
