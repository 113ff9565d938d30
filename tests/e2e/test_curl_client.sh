#!/usr/bin/env bash
# End-to-end test of clients/curl/hexcover.sh against the real hexcover-server.
# usage: test_curl_client.sh SERVER_BINARY     Exit status 0 pass, 1 fail, 77 skipped.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
client=$here/../../clients/curl/hexcover.sh
server=${1:?usage: test_curl_client.sh SERVER_BINARY}
for tool in curl jq python3; do
  command -v $tool >/dev/null || { echo "SKIPPED: $tool is not installed (scripts/setup installs it)"; exit 77; }
done
[[ -x $server ]] || { echo "FAIL: $server is not a built hexcover-server"; exit 1; }

work=$(mktemp -d)
"$server" --port 0 --host 127.0.0.1 --data-dir "$work/data" >"$work/server.log" 2>&1 &
server_pid=$!
cleanup() {
  kill -TERM "$server_pid" 2>/dev/null && wait "$server_pid"
  rm -rf "$work"
}
trap cleanup EXIT

failures=0
check() {  # check DESCRIPTION COMMAND...: runs the command, counts a failure when it is false
  local what=$1
  shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; failures=$((failures + 1)); fi
}

port=""
for _ in $(seq 200); do
  port=$(grep -o '"port":[0-9]*' "$work/server.log" | head -1 | cut -d: -f2)
  [[ -n $port ]] && curl -sf "http://127.0.0.1:$port/readyz" >/dev/null && break
  kill -0 "$server_pid" 2>/dev/null || { echo "FAIL: server exited"; cat "$work/server.log"; exit 1; }
  sleep 0.1
done
[[ -n $port ]] || { echo "FAIL: server did not report its port"; cat "$work/server.log"; exit 1; }
export HEXCOVER_URL=http://127.0.0.1:$port

# The input: an icosphere the test writes itself (642 vertices, 1280 faces).
python3 -c "import sys; sys.path.insert(0, '$here'); from test_python_client import write_icosphere; write_icosphere('$work/sphere.obj')"

"$client" remesh "$work/sphere.obj" --vertices 300 --out "$work/out" --formats obj,off \
  --timeout 150 >"$work/metrics.json" 2>"$work/progress.txt"
status=$?
cat "$work/progress.txt"
check "remesh exits 0" test $status -eq 0
check "progress reaches succeeded" grep -Eq '^job [^ ]+: succeeded' "$work/progress.txt"
id=$(sed -n 's/^submitted .* as job \(.*\)$/\1/p' "$work/progress.txt")
check "the job id is reported" test -n "$id"
curl -sf "$HEXCOVER_URL/v1/jobs/$id/metrics" >"$work/served.json"
check "printed metrics = GET /v1/jobs/{id}/metrics" \
  test "$(jq -S . "$work/metrics.json")" = "$(jq -S . "$work/served.json")"
# The shallowest "vertices"/"faces" leaves are the triangle mesh's own counts.
leaf() { jq "[paths(scalars) as \$p | select(\$p[-1] == \"$1\") | {d: (\$p | length), v: getpath(\$p)}] | sort_by(.d) | .[0].v" "$work/metrics.json"; }
check "OBJ vertex count = metrics" test "$(grep -c '^v ' "$work/out/sphere-triangles.obj")" = "$(leaf vertices)"
check "OBJ face count = metrics" test "$(grep -c '^f ' "$work/out/sphere-triangles.obj")" = "$(leaf faces)"
check "OFF header counts = metrics" \
  test "$(sed -n 2p "$work/out/sphere-triangles.off" | cut -d' ' -f1-2)" = "$(leaf vertices) $(leaf faces)"

"$client" download "$id" "$work/one.ply" >/dev/null 2>&1
check "download by extension writes a PLY" test "$(head -c 3 "$work/one.ply")" = ply

# A quad job: the results offered are downloaded, the quads among them, and no hexagons.
"$client" remesh "$work/sphere.obj" --rosy 4 --vertices 300 --out "$work/quads" --timeout 150 \
  >"$work/quads.json" 2>/dev/null
check "a quad remesh exits 0" test $? -eq 0
check "its quads are downloaded" test -s "$work/quads/sphere-quads.obj"
check "as faces of four corners" \
  test "$(grep '^f ' "$work/quads/sphere-quads.obj" | awk '{print NF - 1}' | sort -u)" = 4
check "and no hexagonal dual" test ! -e "$work/quads/sphere-hexagons.obj"

# 5 vertices are fewer than a closed lattice of the sphere takes: each warning goes to stderr.
"$client" remesh "$work/sphere.obj" --vertices 5 --timeout 150 >"$work/few.json" 2>"$work/few.err"
check "a remesh at 5 vertices exits 0" test $? -eq 0
check "and has warnings" test "$(jq '.warnings | length' "$work/few.json")" -gt 0
check "each of them on stderr" \
  test "$(jq -r '.warnings[] | "warning: \(.)"' "$work/few.json")" = "$(grep '^warning: ' "$work/few.err")"

printf 'not a mesh\n' >"$work/junk.obj"
"$client" remesh "$work/junk.obj" --timeout 60 >"$work/junk.out" 2>"$work/junk.err"
check "a refused file exits 1" test $? -eq 1
check "with the problem on stderr" grep -Eq '^hexcover: (4[0-9][0-9] |job .* failed)' "$work/junk.err"
check "and nothing on stdout" test ! -s "$work/junk.out"

"$client" status no-such-job >/dev/null 2>"$work/404.err"
check "an unknown job exits 1" test $? -eq 1
check "with 404" grep -q '^hexcover: 404 ' "$work/404.err"

"$client" remesh >/dev/null 2>&1
check "bad usage exits 2" test $? -eq 2

kill -TERM "$server_pid" && wait "$server_pid"
check "the server exits 0 on SIGTERM" test $? -eq 0
trap 'rm -rf "$work"' EXIT
((failures == 0)) && echo PASS || { echo "--- server log ---"; tail -40 "$work/server.log"; }
exit $((failures > 0))
