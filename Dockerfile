# The graspforce service: a slim image that runs `graspforce serve` as a non-root user.
#   docker build -t graspforce .
#   docker run --rm -p 127.0.0.1:8000:8000 graspforce        # then open http://127.0.0.1:8000/docs
# Stage 1 compiles the C++ core into a wheel's worth of site-packages in /opt/venv; stage 2 copies
# only that venv, so the image carries no compiler.
FROM python:3.11-slim AS build
RUN apt-get update \
 && apt-get install -y --no-install-recommends g++ cmake make \
 && rm -rf /var/lib/apt/lists/*
WORKDIR /src
COPY pyproject.toml CMakeLists.txt README.md ./
COPY core core
COPY graspforce graspforce
COPY server server
RUN python -m venv /opt/venv \
 && /opt/venv/bin/pip install --no-cache-dir ".[service]"

FROM python:3.11-slim
RUN useradd --create-home --uid 10001 graspforce
COPY --from=build /opt/venv /opt/venv
ENV PATH=/opt/venv/bin:$PATH \
    PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1
USER graspforce
WORKDIR /home/graspforce
# the compiled core loads and answers every method now, so a broken image fails its build
RUN graspforce warmup
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=3s --start-period=10s --retries=3 \
  CMD ["python", "-c", "import sys, urllib.request; sys.exit(urllib.request.urlopen('http://127.0.0.1:8000/healthz', timeout=2).status != 200)"]
# 0.0.0.0 inside the container, so that a published port reaches it; publish it on the host's
# loopback (-p 127.0.0.1:8000:8000) unless it should be reachable from elsewhere
CMD ["graspforce", "serve", "--host", "0.0.0.0", "--port", "8000"]
