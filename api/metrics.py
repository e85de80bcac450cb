"""``/metrics``: Prometheus metrics of the whole deployment, read from the database at each scrape.

Every replica answers with the same figures (checks by status, queue depth, the run-time
histogram of finished checks), whichever process ran the checks. Counts fall when the
retention deletes old checks; Prometheus treats that as a counter reset.
"""

from __future__ import annotations

from collections.abc import Iterator

from prometheus_client import CollectorRegistry, generate_latest
from prometheus_client.core import GaugeMetricFamily, HistogramMetricFamily
from prometheus_client.registry import Collector

from api.store import DURATION_BUCKETS, Store

CONTENT_TYPE = "text/plain; version=0.0.4; charset=utf-8"


class StoreCollector(Collector):
    """Gauges and a histogram computed from the checks table."""

    def __init__(self, store: Store, distributed: bool) -> None:
        self.store = store
        self.distributed = distributed

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
        cumulative, _count, total = self.store.duration_histogram()
        bounds = [*(f"{b:g}" for b in DURATION_BUCKETS), "+Inf"]
        yield HistogramMetricFamily(
            "geomcheck_check_duration_seconds",
            "Run time of finished checks' processes [s]",
            buckets=list(zip(bounds, cumulative, strict=True)),
            sum_value=total,
        )


def render_metrics(store: Store, distributed: bool) -> bytes:
    """The text exposition of :class:`StoreCollector` for ``store``."""
    registry = CollectorRegistry(auto_describe=False)
    registry.register(StoreCollector(store, distributed))
    return generate_latest(registry)
