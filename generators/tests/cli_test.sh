#!/usr/bin/env bash
# CLI contract of wirenet-gen: every bad input gives exactly one stderr line naming the option
# and the value, exit code 2, and leaves no file; good input writes both files, no temp files.
# usage: cli_test.sh PATH/TO/wirenet-gen
set -u
GEN=${1:?usage: cli_test.sh wirenet-gen}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# bad EXPECT CMD...: runs CMD with --out in an empty directory; EXPECT must appear in the message.
# PRE='shell command' prepares that directory first (what it makes is not counted as left over);
# ULIM=KB runs CMD under `ulimit -v KB`.
bad() {
    local expect=$1; shift
    local dir="$WORK/bad"; rm -rf "$dir"; mkdir -p "$dir"
    (cd "$dir" && eval "${PRE:-true}") || fail "'$*': PRE failed"
    local before; before=$(ls -A "$dir")
    (cd "$dir" && { [ -z "${ULIM:-}" ] || ulimit -v "$ULIM"; } && "$GEN" "$@" >stdout.txt 2>stderr.txt); local rc=$?
    local lines; lines=$(wc -l <"$dir/stderr.txt")
    local msg; msg=$(cat "$dir/stderr.txt")
    [ "$rc" -eq 2 ] || fail "'$*': exit $rc, expected 2"
    [ "$lines" -eq 1 ] || fail "'$*': $lines stderr lines: $msg"
    [[ "$msg" == "wirenet-gen"*"error: "* ]] || fail "'$*': bad message format: $msg"
    [[ "$msg" == *"$expect"* ]] || fail "'$*': message lacks '$expect': $msg"
    local left; left=$(ls -A "$dir" | grep -v -e '^stdout.txt$' -e '^stderr.txt$')
    [ "$left" == "$before" ] || fail "'$*': left files: $left"
}

bad "--width must be > 0 (got -3)"           hex --width -3 --out p
bad "--width must be > 0 (got 0)"            hex --width 0 --out p
bad "--height must be a number (got abc)"    hex --height abc --out p
bad "--rise must be > 0 (got -0.01)"         hex --rise=-0.01 --out p
bad "unknown option --colour"                hex --colour red --out p
bad "--axis-distance must be <= --width"     hex --axis-distance 4 --out p
bad "--twist-length + --rise must be <= --height/2" hex --height 0.1 --out p
bad "--node-mass must be a number > 0 or 'wire' (got heavy)" hex --node-mass heavy --out p
bad "--areal-mass must be > 0 (got 0)"       hex --areal-mass 0 --out p
bad "--snap must be < 0.5 (got 0.7)"         hex --snap 0.7 --out p
bad "give --node-diameter or --node-radius, not both" hex --node-diameter 0.01 --node-radius 0.005 --out p
bad "--node-radius must be > 0 (got 0)"      hex --node-radius 0 --out p
bad "give --hex-node-diameter or --hex-node-radius, not both" compound --hex-node-diameter 0.01 --hex-node-radius 0.005 --out p
bad "--placement must be twist, wire, corner or symmetric (got middle)" hex --placement middle --out p
bad "--placement must be twist, wire, corner or symmetric (got Corner)" compound --placement Corner --out p
bad "--placement must not be empty (got '')" hex --placement= --out p
bad "--selvedge must be loop, none or sides (got yes)" hex --selvedge yes --out p
bad "--selvedge must be loop, none or sides (got None)" compound --selvedge None --out p
bad "--out is required"                      hex --width 2
bad "--width needs a value"                  hex --width
bad "--zlo must be below the nodes (got 0.5)" hex --zlo 0.5 --out p
bad "--cell must be <= --width (got 5 > 3)"  square --cell 5 --out p
bad "--elements must be >= 1 (got 0)"        square --elements 0 --out p
bad "--elements must be an integer (got 2.5)" square --elements 2.5 --out p
bad "--rope-mass must be a number (got nan)" square --rope-mass nan --out p
bad "--ties must be >= 0 (got -1)"           compound --ties -1 --out p
bad "--hex-node-diameter must be > 0 (got -1)" compound --hex-node-diameter -1 --out p
bad "--square-node-diameter must be a number (got x)" compound --square-node-diameter x --out p
bad "--length must be > 0 (got -2)"          beam --length -2 --out p
bad "--elements must be >= 1 (got 0)"        beam --elements 0 --out p
bad "--density must be a number (got steel)" beam --density steel --out p
bad "--radius must be > 0 (got 0)"           shape spheroid --radius 0 --out s.stl
bad "--height must be > 0 (got -1)"          shape cone --height -1 --out s.stl
bad "--resolution must be an integer (got fine)" shape cone --resolution fine --out s.stl
bad "--tip-radius must be < --radius (got 0.5 >= 0.34)" shape cone --tip-radius 0.5 --out s.stl
bad "--tip-radius must be >= 0 (got -0.1)" shape cone --tip-radius -0.1 --out s.stl
bad "--resolution must be >= 8 (got 3)"      shape spheroid --resolution 3 --out s.stl
bad "--corner-cut must be < --side/2 (got 0.3 >= 0.225)" shape truncated-cube --corner-cut 0.3 --out s.stl
bad "--side must be > 0 (got -0.45)"         shape truncated-cube --side -0.45 --out s.stl
bad "unknown shape blob"                     shape blob --out s.stl
bad "unknown subcommand hexagon"             hexagon --out p
bad "--out cannot write"                     hex --out "$WORK/no/such/dir/p"

# Non-finite and out-of-range numbers (strtod accepts inf and nan; issue #14).
bad "--width must be a number (got inf)"     hex --width inf --out p
bad "--height must be a number (got nan)"    hex --height=nan --out p
bad "--rope-mass must be a number (got -inf)" square --rope-mass -inf --out p
bad "--hex-areal-mass must be a number (got inf)" compound --hex-areal-mass inf --out p
bad "--mass must be a number (got nan)"      shape truncated-cube --mass nan --out s.stl
bad "--node-mass must be a number > 0 or 'wire' (got inf)" hex --node-mass inf --out p
bad "--node-mass must be a number > 0 or 'wire' (got 1e400)" hex --node-mass 1e400 --out p
bad "--width must be <= 1000000000 (got 1e308)" hex --width 1e308 --out p
bad "--diameter must be <= 1000000000 (got 1e308)" beam --diameter 1e308 --out p
bad "--zlo must be between -1000000000 and 1000000000 (got -1e12)" hex --zlo -1e12 --out p
bad "--elements must be <= 1000000000 (got 99999999999)" beam --elements 99999999999 --out p
bad "--resolution must be <= 1024 (got 100000)" shape spheroid --resolution 100000 --out s.stl
bad "--max-nodes must be >= 1 (got 0)"       hex --max-nodes 0 --out p
# Finite options whose derived quantities over- or underflow.
bad "atom 1 mass is not a finite positive number (got 0) with --diameter 1e-200" beam --diameter 1e-200 --out p
bad "atom 1 density is not a finite positive number (got inf) with --node-diameter 1e-120" hex --node-diameter 1e-120 --out p
bad "volume is not a finite positive number (got 0) with --radius 1e-200 --height 1e-200" shape spheroid --radius 1e-200 --height 1e-200 --out s.stl
# Size guard: estimated before anything is allocated.
bad "--width 1e6 --height 1e6 gives about"   hex --width 1e6 --height 1e6 --out p
bad "more than --max-nodes 5000000"          hex --width 1e6 --height 1e6 --out p
bad "--cell 1e-6 gives about"                square --cell 1e-6 --out p
bad "--elements 100000000 gives about 1e+08 nodes" beam --elements 100000000 --out p
bad "more than --max-nodes 100"              compound --max-nodes 100 --out p
ULIM=150000 bad "out of memory"              hex --width 60 --height 60 --out p
# All-or-nothing outputs: every target checked before anything is written.
PRE='mkdir p.json' bad "--out cannot write p.json (is a directory)" hex --out p
PRE='mkdir p.data' bad "--out cannot write p.data (is a directory)" beam --out p
PRE='mkdir s.json' bad "--out cannot write s.json (is a directory)" shape cone --out s.stl
PRE='mkdir sub' bad "--out must be a file prefix, not a folder (got sub/)" square --out sub/
PRE='touch file' bad "--out cannot write file/p.data (file is not a folder)" hex --out file/p
bad "--out must name the STL file, not its .json (got s.json)" shape cone --out s.json
# fence: its own options, the panel options it reuses, and a third output file.
bad "--net must be hex, square or compound (got chain)" fence --net chain --out p
bad "--modules must be >= 1 (got 0)"         fence --modules 0 --out p
bad "--axis-distance must be <= --spacing - 2 x --post-gap (got 20 > 9.7)" fence --axis-distance 20 --out p
bad "--cell must be <= (--height - 2 x --shackle-gap) (got 6 > 4.9)" fence --net square --cell 6 --out p
bad "--shackle-gap must be > 0.0164, a net node's radius plus a support rope node's radius (got 0.010)" fence --shackle-gap 0.010 --out p
bad "--post-gap must be > 0.1054, a net node's radius plus a post node's radius (got 0.10)" fence --post-gap 0.10 --out p
bad "--post-gap must be < --spacing/2 (got 2.0)" fence --spacing 4 --post-gap 2.0 --out p
bad "--post-gap must be > 0 (got 0)"         fence --post-gap 0 --out p
bad "--post-gap must be < --spacing/2 (got 5.05, its default from" fence --post-node-diameter 10 --out p
bad "--brakes must be <= 5"                  fence --brakes 6 --out p
bad "more than --max-nodes 100"              fence --max-nodes 100 --out p
PRE='mkdir p.shackles' bad "--out cannot write p.shackles (is a directory)" fence --out p

# --help on every subcommand: exit 0, options with units and defaults.
for sub in hex square compound beam fence "shape spheroid" "shape cone" "shape truncated-cube"; do
    out=$("$GEN" $sub --help 2>&1); rc=$?
    [ $rc -eq 0 ] || fail "$sub --help exit $rc"
    [[ "$out" == *"(default: "* && "$out" == *"[m]"* && "$out" == *"--out"* ]] || fail "$sub --help text"
done

# Good runs: both files, no temporary files, JSON parses, counts agree with the data file.
dir="$WORK/good"; mkdir -p "$dir"; cd "$dir" || exit 1
for sub in hex square compound beam; do
    "$GEN" $sub --out "$sub" >/dev/null 2>err.txt || fail "$sub default run failed: $(cat err.txt)"
    [ -s "$sub.data" ] && [ -s "$sub.json" ] || fail "$sub: missing output"
    head -1 "$sub.data" | grep -q "^LIGGGHTS data file from wirenet-gen $sub" || fail "$sub: data header"
    atoms=$(awk '/ atoms$/{print $1; exit}' "$sub.data")
    grep -q "\"atoms\": $atoms," "$sub.json" || fail "$sub: json atom count differs from data ($atoms)"
done
for shape in spheroid cone truncated-cube; do
    "$GEN" shape $shape --out "$shape.stl" >/dev/null || fail "shape $shape failed"
    head -1 "$shape.stl" | grep -q "^solid" && tail -1 "$shape.stl" | grep -q "^endsolid" || fail "$shape: not ASCII STL"
    [ -s "$shape.json" ] || fail "$shape: json missing"
done
"$GEN" fence --modules 1 --spacing 4 --height 3 --out fence >/dev/null 2>err.txt || fail "fence run failed: $(cat err.txt)"
[ -s fence.data ] && [ -s fence.json ] && [ -s fence.shackles ] || fail "fence: missing output"
grep -q '^ropes ' fence.shackles && grep -q '^shackles ' fence.shackles || fail "fence.shackles: no ropes/shackles lines"
grep -q '"inertia"' truncated-cube.json || fail "truncated-cube.json lacks the inertia tensor"
left=$(ls -A | grep tmp)
[ -z "$left" ] || fail "temporary files left: $left"
# A node size given as a radius is twice that as the diameter column of the data file.
"$GEN" square --node-radius 0.004 --out sq_r >/dev/null || fail "square --node-radius failed"
awk '/^Atoms/{a=1; next} a && NF >= 7 {print $6; exit}' sq_r.data | grep -qx "0.008" ||
    fail "square --node-radius 0.004 did not give diameter 0.008"
# --placement twist is the default, byte for byte (the header repeats the command line); the
# JSON records the placement.
for sub in hex compound; do
    "$GEN" $sub --placement twist --out "${sub}_twist" >/dev/null || fail "$sub --placement twist failed"
    cmp -s <(tail -n +2 "$sub.data") <(tail -n +2 "${sub}_twist.data") ||
        fail "$sub --placement twist differs from the default"
    grep -q '"placement": "twist"' "$sub.json" || fail "$sub.json lacks \"placement\": \"twist\""
    for placement in wire corner symmetric; do
        "$GEN" $sub --placement $placement --out "${sub}_$placement" >/dev/null || fail "$sub --placement $placement failed"
        grep -q "\"placement\": \"$placement\"" "${sub}_$placement.json" || fail "${sub}_$placement.json lacks the placement"
    done
done
# --selvedge loop is the default, byte for byte; none drops the selvedge bonds (type 3).
"$GEN" hex --selvedge loop --out hex_loop >/dev/null || fail "hex --selvedge loop failed"
cmp -s <(tail -n +2 hex.data) <(tail -n +2 hex_loop.data) || fail "hex --selvedge loop differs from the default"
grep -q '"selvedge": "loop"' hex.json || fail "hex.json lacks \"selvedge\": \"loop\""
"$GEN" hex --selvedge none --out hex_bare >/dev/null || fail "hex --selvedge none failed"
grep -q '"selvedge": "none"' hex_bare.json || fail "hex_bare.json lacks \"selvedge\": \"none\""
awk '/^Bonds/{b=1; next} b && NF == 4 && $2 == 3 {n++} END {exit n > 0}' hex_bare.data ||
    fail "hex --selvedge none still has selvedge bonds"
# sides: the selvedge of the x edges only; on YADE's tensile net exactly its 239 links.
"$GEN" hex --width 0.96 --height 0.52 --placement symmetric --selvedge sides --out hex_sides |
    grep -q "178 atoms, 239 bonds (DT 81, SW 144, selvedge 14)" || fail "hex --selvedge sides: not YADE's 239 links"
grep -q '"selvedge": "sides"' hex_sides.json || fail "hex_sides.json lacks \"selvedge\": \"sides\""
# Corner: the first atom is the lower-left corner (-W/2, -H/2), then the top of the edge twist.
awk '/^Atoms/{a=1; next} a && NF >= 7 {print $2, $3, $4; n++} n == 2 {exit}' hex_corner.data |
    tr '\n' ' ' | grep -qx "4 -1.5 -1.5 2 -1.5 -1.46 " || fail "hex --placement corner does not start at the corner"
# Symmetric: YADE's tensile-test net (hexaNet(0.0108, [0,0,0], 1.0, 0.55, 0.08, 0.04, 0.04,
# startAtCorner=False, isSymmetric=True)): 178 nodes, DT 81, SW 144 and the selvedge loop.
"$GEN" hex --width 0.96 --height 0.52 --placement symmetric --node-radius 0.0108 --out yade_tensile |
    grep -q "178 atoms, 265 bonds (DT 81, SW 144, selvedge 40)" || fail "hex --placement symmetric: not YADE's tensile net"
# A failed run does not clobber an earlier good output.
cp hex.data before.data
"$GEN" hex --width -1 --out hex 2>/dev/null
cmp -s hex.data before.data || fail "failed run modified an existing output"

if [ "$fails" -ne 0 ]; then echo "$fails CLI checks failed"; exit 1; fi
echo "all CLI checks passed"
