# The geomcheck HTTP service.
#   docker build -t geomcheck .
#   docker run --rm -p 8000:8000 -v geomcheck-data:/data geomcheck
# Settings are GEOMCHECK_* environment variables (docs/api.md); reports live in /data.
# The same image runs both roles of the distributed mode (docs/deploy.md, compose.yaml):
# `geomcheck serve ...` (an API replica) and `geomcheck worker --concurrency N` (checks).
FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    GEOMCHECK_DATA_DIR=/data

WORKDIR /app

# The dependencies, read from pyproject.toml, in their own layer: a code change does not reinstall them.
COPY pyproject.toml README.md ./
RUN python -c "import tomllib; print('\n'.join(tomllib.load(open('pyproject.toml', 'rb'))['project']['dependencies']))" \
        > /tmp/requirements.txt \
    && pip install -r /tmp/requirements.txt \
    && rm /tmp/requirements.txt

COPY geomcheck ./geomcheck
COPY api ./api
RUN pip install --no-deps . && rm -rf build

RUN useradd --system --uid 10001 --user-group --home-dir /data --shell /usr/sbin/nologin geomcheck \
    && mkdir -p /data \
    && chown geomcheck:geomcheck /data
USER geomcheck
VOLUME ["/data"]
EXPOSE 8000

# /readyz, as the load balancers of docs/deploy.md probe: the database and (distributed mode)
# the broker answer. A worker container overrides it (compose.yaml: geomcheck worker --ping).
HEALTHCHECK --interval=30s --timeout=5s --start-period=30s --retries=3 \
    CMD ["python", "-c", "import urllib.request; urllib.request.urlopen('http://127.0.0.1:8000/readyz', timeout=4)"]

CMD ["geomcheck", "serve", "--host", "0.0.0.0", "--port", "8000"]
