#!/usr/bin/env bash
# Client of the hexcover remeshing service (HTTP API v1) with curl and jq.
#
#   hexcover.sh [--url URL] remesh MESH [--vertices N | --edge-length L] [--rosy 4|6]
#               [--sizing uniform|curvature] [--placement balanced|on_surface] [--feature-angle DEG]
#               [--d-sing D] [--out DIR] [--formats obj,ply,...]
#               [--meshes triangles,quads,hexagons,textured] [--timeout SECONDS]
#       upload MESH, follow the job on stderr, download the results to DIR, print the metrics
#   hexcover.sh [--url URL] status|metrics|cancel JOB_ID
#   hexcover.sh [--url URL] download JOB_ID FILE [--mesh triangles|quads|hexagons|textured]
#               [--format F]
#
# URL defaults to $HEXCOVER_URL or http://localhost:8080. Exit status: 0 success, 1 the service
# refused the request or the job failed (the problem document's title and detail on stderr),
# 2 bad usage.
set -euo pipefail

url=${HEXCOVER_URL:-http://localhost:8080}
body=$(mktemp)
trap 'rm -f "$body"' EXIT

usage() {
  sed -n '3,17p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}
die() {
  echo "hexcover: $*" >&2
  exit 1
}

# api METHOD PATH [curl args...]: the response body goes to $body; refusals end the script with
# the problem document's status, title and detail.
api() {
  local method=$1 path=$2
  shift 2
  local status
  status=$(curl -sS -X "$method" -o "$body" -w '%{http_code}' -H 'Accept: application/json' "$@" \
    "$url$path") || die "cannot reach $url"
  if ((status >= 400)); then
    die "$(jq -r '"\(.status) \(.title)" + (if .detail then ": \(.detail)" else "" end)' "$body" \
      2>/dev/null || echo "HTTP $status")"
  fi
}

progress_line() {
  jq -r '"job \(.id): \(.state)"
         + (if .stage then " · \(.stage)" else "" end)
         + (if .state == "running" then " · \(.progress * 100 | floor)%" else "" end)
         + (if .state == "queued" and .queue_position != null then " · queue position \(.queue_position)" else "" end)' "$body"
}

remesh() {
  local mesh="" out="" formats=obj meshes=triangles,quads,hexagons,textured timeout=3600 query=()
  while (($#)); do
    case $1 in
      --vertices) query+=("vertices=$2"); shift 2 ;;
      --edge-length) query+=("edge_length=$2"); shift 2 ;;
      --rosy) query+=("rosy=$2"); shift 2 ;;
      --sizing) query+=("sizing=$2"); shift 2 ;;
      --placement) query+=("placement=$2"); shift 2 ;;
      --feature-angle) query+=("feature_angle=$2"); shift 2 ;;
      --d-sing) query+=("d_sing=$2"); shift 2 ;;
      --out) out=$2; shift 2 ;;
      --formats) formats=$2; shift 2 ;;
      --meshes) meshes=$2; shift 2 ;;
      --timeout) timeout=$2; shift 2 ;;
      -*) usage ;;
      *) [[ -z $mesh ]] || usage; mesh=$1; shift ;;
    esac
  done
  [[ -n $mesh ]] || usage
  [[ -f $mesh ]] || die "no file $mesh"
  local joined
  joined=$(IFS='&'; echo "${query[*]}")

  # The raw body, streamed from the file (-T); the server detects the format from the bytes.
  api POST "/v1/jobs?$joined" -T "$mesh" -H 'Content-Type: application/octet-stream'
  local id
  id=$(jq -r .id "$body")
  echo "submitted $mesh as job $id" >&2

  local state last="" deadline=$((SECONDS + timeout))
  while :; do
    api GET "/v1/jobs/$id"
    local line
    line=$(progress_line)
    [[ $line == "$last" ]] || echo "$line" >&2
    last=$line
    state=$(jq -r .state "$body")
    case $state in
      succeeded) break ;;
      failed) die "job $id failed: $(jq -r '.error | "\(.title)" + (if .detail then ": \(.detail)" else "" end)' "$body")" ;;
      canceled) die "job $id was canceled" ;;
    esac
    ((SECONDS < deadline)) || die "job $id is still $state after $timeout s"
    sleep 0.5
  done

  if [[ -n $out ]]; then
    mkdir -p "$out"
    local stem offered
    stem=$(basename "${mesh%.*}")
    offered=$(jq -r '.links.results[] | "\(.mesh).\(.format)"' "$body")
    local m f
    for m in ${meshes//,/ }; do
      for f in ${formats//,/ }; do
        grep -qx "$m.$f" <<<"$offered" || continue
        download "$id" "$out/$stem-$m.$f" --mesh "$m" --format "$f"
        echo "wrote $out/$stem-$m.$f ($(stat -c %s "$out/$stem-$m.$f") bytes)" >&2
      done
    done
  fi
  api GET "/v1/jobs/$id/metrics"
  jq -r '.warnings[]? | "warning: \(.)"' "$body" >&2
  jq . "$body"
}

download() {
  local id=$1 file=$2 mesh=triangles format=""
  shift 2
  while (($#)); do
    case $1 in
      --mesh) mesh=$2; shift 2 ;;
      --format) format=$2; shift 2 ;;
      *) usage ;;
    esac
  done
  [[ -n $format ]] || format=${file##*.}
  local status
  status=$(curl -sS -o "$file.part" -w '%{http_code}' \
    "$url/v1/jobs/$id/result?mesh=$mesh&format=$format") || die "cannot reach $url"
  if ((status >= 400)); then
    cp "$file.part" "$body" && rm -f "$file.part"
    die "$(jq -r '"\(.status) \(.title)" + (if .detail then ": \(.detail)" else "" end)' "$body")"
  fi
  mv "$file.part" "$file"
}

[[ ${1:-} == --url ]] && { url=$2; shift 2; }
url=${url%/}
command -v jq >/dev/null || die "jq is not installed (Debian package jq)"
(($#)) || usage
command=$1
shift
case $command in
  remesh) remesh "$@" ;;
  status) (($# == 1)) || usage; api GET "/v1/jobs/$1"; jq . "$body" ;;
  metrics) (($# == 1)) || usage; api GET "/v1/jobs/$1/metrics"; jq . "$body" ;;
  cancel) (($# == 1)) || usage; api DELETE "/v1/jobs/$1" ;;
  download) (($# >= 2)) || usage; download "$@" ;;
  *) usage ;;
esac
