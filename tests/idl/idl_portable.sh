#!/bin/sh
# idl_portable.sh lint|fastddsgen IDL -- see tests/idl/CMakeLists.txt.
# Exit 0 pass, 1 fail, 77 skipped (CTest SKIP_RETURN_CODE).
set -u
mode=$1
idl=$2
[ -f "$idl" ] || { echo "FAIL: no such IDL file: $idl"; exit 1; }

case $mode in
lint)
  # One identifier per line, tagged: T <name> for every struct, M <name> for every member of one.
  # Comments and preprocessor lines are stripped first; members are `<type> <name>[...];` lines
  # inside a struct body.
  idents=$(sed -e 's://.*$::' -e '/^[[:space:]]*#/d' "$idl" | awk '
    /struct[[:space:]]+[A-Za-z_][A-Za-z0-9_]*[[:space:]]*\{/ {
      line = $0
      sub(/.*struct[[:space:]]+/, "", line); sub(/[[:space:]]*\{.*/, "", line)
      print "T " line
      if ($0 !~ /@final[[:space:]]+struct/) print "NOTFINAL " line
      in_struct = 1; next
    }
    in_struct && /\};/ { in_struct = 0; next }
    in_struct && /;/ {
      line = $0
      sub(/;.*/, "", line); sub(/\[.*/, "", line); sub(/[[:space:]]+$/, "", line)
      n = split(line, words, /[[:space:]>]+/)
      if (n >= 2) print "M " words[n]
    }')
  status=0
  notfinal=$(echo "$idents" | awk '$1 == "NOTFINAL" { print $2 }')
  if [ -n "$notfinal" ]; then
    echo "FAIL: structs without @final in $idl:"; echo "$notfinal"; status=1
  fi
  structs=$(echo "$idents" | awk '$1 == "T"' | wc -l)
  [ "$structs" -gt 0 ] || { echo "FAIL: no struct found in $idl"; exit 1; }
  clashes=$(echo "$idents" | awk '
    $1 == "T" { types[tolower($2)] = $2 }
    $1 == "M" { members[tolower($2)] = $2 }
    END { for (m in members) if (m in types) print "member " members[m] " vs type " types[m] }')
  if [ -n "$clashes" ]; then
    echo "FAIL: case-insensitive clashes between member and type names in $idl:"
    echo "$clashes"; status=1
  fi
  [ $status -eq 0 ] && echo "PASS: $structs structs, all @final, no member/type name clash"
  exit $status
  ;;
fastddsgen)
  gen=$(command -v fastddsgen) || {
    echo "SKIPPED: fastddsgen not installed (Debian 12: apt-get install fastddsgen default-jre-headless)"
    exit 77
  }
  command -v java >/dev/null || { echo "SKIPPED: fastddsgen needs java, which is not installed"; exit 77; }
  out=$(mktemp -d "${TMPDIR:-/tmp}/dammloam-fastddsgen.XXXXXX") || exit 1
  trap 'rm -rf "$out"' EXIT
  # Exactly as a Fast DDS user would run it: no -cs (case-sensitive identifiers), no -I tricks.
  mkdir "$out/gen" && "$gen" -replace -d "$out/gen" "$idl" > "$out/log" 2>&1
  rc=$?
  cat "$out/log"
  name=$(basename "$idl" .idl)
  if [ $rc -ne 0 ] || grep -qiE 'error:|exception' "$out/log"; then
    echo "FAIL: fastddsgen (without -cs) rejected $idl (exit $rc)"; exit 1
  fi
  for f in "$name.h" "$name.cxx" "${name}PubSubTypes.h" "${name}PubSubTypes.cxx"; do
    [ -s "$out/gen/$f" ] || { echo "FAIL: fastddsgen wrote no $f"; exit 1; }
  done
  echo "PASS: fastddsgen generated $name.h/.cxx and ${name}PubSubTypes.h/.cxx without -cs"
  ;;
*)
  echo "usage: idl_portable.sh lint|fastddsgen IDL"; exit 1
  ;;
esac
