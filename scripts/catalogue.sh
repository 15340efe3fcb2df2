#!/usr/bin/env bash
# The lattice catalogue: fills small inputs and the real femur with `tpmsfill fill`, one run per
# lattice feature, renders each output with `tpmsfill render`, draws a messy scan's defects with
# `tpmsfill check --picture`, and writes the page that shows them (docs/catalogue.md). Same
# commands, same images: every step is deterministic.
#
#   bash scripts/catalogue.sh [OUT_DIR] [IMAGE...]
#
#   OUT_DIR  where the PNGs go (default: the repository's docs/images); the page goes to
#            docs/catalogue.md when OUT_DIR is docs/images, else to OUT_DIR/catalogue.md
#   IMAGE    make only these images: names or shell patterns ('types-*', 'grade-*'); the page
#            is still written whole, from every PNG that OUT_DIR holds
#
# Environment: BUILD_DIR (default build); CATALOGUE_NO_BUILD=1 skips setup and build (use what
# BUILD_DIR holds); KEEP_DIR=DIR keeps the inputs and the filled meshes there.
#
# An image whose fill needs an option or lattice this tpmsfill does not have yet is reported
# "pending" and skipped, and the page shows its command without a picture; run the script
# again once the option exists. Each feature is one function below (image_*): to add one, write
# a function and list it in `features`.
# shellcheck disable=SC2016,SC2317  # backquotes are markdown; image_* run through "$feature"
set -euo pipefail
caller="$PWD"
cd "$(dirname "$0")/.."
out_dir="${1:-docs/images}"
[[ -z "${1:-}" || "$out_dir" == /* ]] || out_dir="$caller/$out_dir"
shift || true
patterns=("$@")
build_dir="${BUILD_DIR:-build}"

if [[ "${CATALOGUE_NO_BUILD:-}" != 1 ]]; then
  bash scripts/setup.sh
  bash scripts/build.sh "$build_dir" >/dev/null
fi
tpmsfill="$PWD/$build_dir/tpmsfill"
[[ -x "$tpmsfill" ]] || { echo "catalogue: $tpmsfill is missing (build it first)" >&2; exit 2; }
"$tpmsfill" render --help >/dev/null 2>&1 ||
  { echo "catalogue: this tpmsfill has no render command" >&2; exit 2; }
mkdir -p "$out_dir"
out_dir="$(cd "$out_dir" && pwd)"
if [[ "$out_dir" == "$PWD/docs/images" ]]; then
  page="$PWD/docs/catalogue.md" link_prefix="images/"
else
  page="$out_dir/catalogue.md" link_prefix=""
fi
if [[ -n "${KEEP_DIR:-}" ]]; then
  work=$(cd "$caller" && mkdir -p "$KEEP_DIR" && cd "$KEEP_DIR" && pwd)
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
fill_help=$("$tpmsfill" fill --help)

# --- inputs (written into $work; the commands below run there and name them relatively) -------

# cube X [Y Z]: an axis-aligned box from (0,0,0) to (X,Y,Z) (a cube when Y and Z are left out),
# 12 outward triangles.
cube() {
  local x=$1 y=${2:-$1} z=${3:-$1}
  cat <<EOF
OFF
8 12 0
0 0 0
$x 0 0
$x $y 0
0 $y 0
0 0 $z
$x 0 $z
$x $y $z
0 $y $z
3 0 2 1
3 0 3 2
3 4 5 6
3 4 6 7
3 0 1 5
3 0 5 4
3 1 2 6
3 1 6 5
3 2 3 7
3 2 7 6
3 3 0 4
3 3 4 7
EOF
}
cube 10 >"$work/cube10.off"
cube 20 >"$work/cube20.off"
# Plates for seed 004's ring figures, whose rings lie in the xy plane.
cube 20 20 5 >"$work/plate20.off"
cube 40 40 5 >"$work/plate40.off"
# A cylinder of radius 10 mm around the z axis from z = 0 to 20 mm: 96 sides, fanned end caps.
awk -v n=96 -v r=10 -v h=20 'BEGIN {
  pi = atan2(0, -1)
  print "OFF"; print 2 * n + 2, 4 * n, 0
  for (k = 0; k < 2; ++k) for (i = 0; i < n; ++i)
    printf "%.9f %.9f %g\n", r * cos(2 * pi * i / n), r * sin(2 * pi * i / n), k * h
  print 0, 0, 0; print 0, 0, h
  for (i = 0; i < n; ++i) {
    j = (i + 1) % n
    print 3, i, j, n + j; print 3, i, n + j, n + i        # side, outward
    print 3, 2 * n, j, i; print 3, 2 * n + 1, n + i, n + j  # bottom (down), top (up)
  }
}' >"$work/cylinder.off"
# Debian's femur (libcgal-demo): 1 unit long, centred on the origin; --scale 35 makes it the
# benchmark's 35 mm bone (x -6.9..6.9, y -5.9..5.9, z -17.5..17.5 mm, the head at -z).
femur_tarball=/usr/share/doc/libcgal-demo/data.tar.gz
have_femur=0
if [[ -f "$femur_tarball" ]]; then
  tar -xzf "$femur_tarball" -C "$work" --strip-components=2 data/meshes/femur.off && have_femur=1
fi

# Seed 004's surfaces: the procedural dome and wave, and libcgal-demo's face and blade.
python3 scripts/surfaces.py "$work"
if [[ -f "$femur_tarball" ]]; then
  tar -xzf "$femur_tarball" -C "$work" --strip-components=2 data/meshes/nefertiti.off \
    data/meshes/blade.off || true
fi

# Seed 003's structures (issue 13), as ITDF files made by `tpmsfill field fit`: the skull CT
# libcgal-demo ships (bone above 2.9), and a sponge: 48³ cells, distance to the nearest of 40
# random pore centres minus 0.11 (the unit cube), the solid outside the pores.
have_skull=0
if [[ -f "$femur_tarball" ]] && tar -xzf "$femur_tarball" -C "$work" --strip-components=2 \
  data/images/skull_2.9.inr 2>/dev/null; then
  "$tpmsfill" field fit "$work/skull_2.9.inr" "$work/skull.itdf" --coefficients 32 \
    --solid 2.9 inf --quiet && have_skull=1
fi
# Seed 001's solid with a material (issue 18): Debian's bunny, fitted in image_material.
if [[ -f "$femur_tarball" ]]; then
  tar -xzf "$femur_tarball" -C "$work" --strip-components=2 data/meshes/bunny00.off || true
fi
python3 scripts/sponge_field.py "$work/sponge.tdf"
"$tpmsfill" field fit "$work/sponge.tdf" "$work/sponge.itdf" --coefficients 24 --solid 0 inf --quiet
"$tpmsfill" field fit "$work/sponge.tdf" "$work/sponge-sheet.itdf" --coefficients 24 \
  --surface 0.05 --thickness 0.5 --size 20 20 20 --quiet

# --- one image ---------------------------------------------------------------------------------

names=() fill_commands=() render_commands=() notes=() statuses=()
now() { date +%s.%N; }

# shot NAME INPUT "RENDER OPTIONS" "FILL OPTIONS" "what to look for"
# Runs `tpmsfill fill INPUT NAME.stl FILL OPTIONS` in $work and renders NAME.stl to
# OUT_DIR/NAME.png at --size 480 with RENDER OPTIONS. Records the commands and the note for the
# page whether or not the image is made in this run.
# The command is `fill`, or $shot_command where an image needs another (conformal).
shot_command=fill
shot() {
  local name=$1 input=$2 render_options=$3 fill_options=$4 note=$5
  local command=$shot_command
  local fill_cmd="tpmsfill $command $input $name.stl $fill_options"
  local render_cmd="tpmsfill render $name.stl $name.png --size 480${render_options:+ $render_options}"
  names+=("$name") fill_commands+=("$fill_cmd") render_commands+=("$render_cmd") notes+=("$note")
  local status=""
  if ((${#patterns[@]})); then
    status="not selected"
    for p in "${patterns[@]}"; do
      # shellcheck disable=SC2053  # the pattern is meant to match as a glob
      [[ "$name" == $p ]] && status=""
    done
  fi
  if [[ -z "$status" && ! -f "$work/$input" ]]; then
    status="skipped: no $input (apt-get install libcgal-demo)"
  fi
  if [[ -z "$status" && "$input" == femur.off && $have_femur == 0 ]]; then
    status="skipped: no $femur_tarball (apt-get install libcgal-demo)"
  fi
  if [[ -z "$status" ]]; then
    local word
    for word in $fill_options; do
      if [[ "$word" == --* ]] && ! grep -qE -- "(^|[ ,])$word([ ,=]|$)" \
        <<<"$([[ $command == fill ]] && echo "$fill_help" || "$tpmsfill" "$command" --help 2>/dev/null)"; then
        status="pending: this tpmsfill $command has no $word"
        break
      fi
    done
  fi
  if [[ -z "$status" && "$command" != fill ]] && ! "$tpmsfill" "$command" --help >/dev/null 2>&1; then
    status="pending: this tpmsfill has no $command"
  fi
  if [[ -n "$status" ]]; then
    statuses+=("$status")
    [[ "$status" == "not selected" ]] || printf '%-28s %s\n' "$name" "$status"
    return 0
  fi

  local t0 t1 t2 code=0
  t0=$(now)
  # shellcheck disable=SC2086  # the options are words
  (cd "$work" && "$tpmsfill" "$command" "$input" "$name.stl" $fill_options --quiet) \
    2>"$work/$name.err" || code=$?
  t1=$(now)
  if ((code != 0)); then
    local why
    why=$(head -n 1 "$work/$name.err")
    if ((code == 2)) && grep -qiE "unknown lattice|not expected|unknown option" "$work/$name.err"; then
      status="pending: $why"
    else
      status="FAILED (exit $code): $why"
    fi
    statuses+=("$status")
    printf '%-28s %s\n' "$name" "$status"
    return 0
  fi
  # shellcheck disable=SC2086
  if ! (cd "$work" && "$tpmsfill" render "$name.stl" "$out_dir/$name.png" --size 480 \
    $render_options --quiet) 2>"$work/$name.err"; then
    status="FAILED: $(head -n 1 "$work/$name.err")"
    statuses+=("$status")
    printf '%-28s %s\n' "$name" "$status"
    return 0
  fi
  t2=$(now)
  local bytes triangles kb
  bytes=$(stat -c %s "$work/$name.stl")
  triangles=$(((bytes - 84) / 50))  # binary STL: 84-byte header, 50 bytes a triangle
  kb=$(($(stat -c %s "$out_dir/$name.png") / 1024))
  status=$(awk -v n="$triangles" -v f="$t1" -v s="$t0" -v r="$t2" -v kb="$kb" \
    'BEGIN { printf "made: %d triangles, fill %.1f s, render %.1f s, %d KB", n, f - s, r - f, kb }')
  ((kb < 250)) || status+=" (over 250 KB)"
  statuses+=("$status")
  printf '%-28s %s\n' "$name" "$status"
  [[ -n "${KEEP_DIR:-}" ]] || rm -f "$work/$name.stl"
}

# held_back NAME INPUT: true (and NAME's status recorded) when NAME is not to be made now: not
# among the IMAGE patterns, or INPUT missing from $work.
held_back() {
  local name=$1 input=$2 status="" p
  if ((${#patterns[@]})); then
    status="not selected"
    for p in "${patterns[@]}"; do
      # shellcheck disable=SC2053  # the pattern is meant to match as a glob
      [[ "$name" == $p ]] && status=""
    done
  fi
  [[ -n "$status" || -f "$work/$input" ]] || status="skipped: no $input (apt-get install libcgal-demo)"
  [[ -n "$status" ]] || return 1
  statuses+=("$status")
  [[ "$status" == "not selected" ]] || printf '%-28s %s\n' "$name" "$status"
}

# check_shot NAME INPUT "CHECK OPTIONS" "what to look for"
# Runs `tpmsfill check INPUT --picture OUT_DIR/NAME.png --size 480 CHECK OPTIONS` in $work: the
# input's defects drawn over it. Exit 1 (not valid) is what a messy input gives, not a failure.
check_shot() {
  local name=$1 input=$2 check_options=$3 note=$4
  local check_cmd="tpmsfill check $input --picture $name.png --size 480${check_options:+ $check_options}"
  names+=("$name") fill_commands+=("$check_cmd") render_commands+=("") notes+=("$note")
  local status="" code=0
  held_back "$name" "$input" && return 0
  local t0 t1
  t0=$(now)
  # shellcheck disable=SC2086  # the options are words
  (cd "$work" && "$tpmsfill" check "$input" --picture "$out_dir/$name.png" --size 480 \
    $check_options >"$work/$name.out" 2>"$work/$name.err") || code=$?
  t1=$(now)
  if ((code > 1)); then
    status="FAILED (exit $code): $(head -n 1 "$work/$name.err")"
  else
    status=$(awk -v f="$t1" -v s="$t0" -v kb="$(($(stat -c %s "$out_dir/$name.png") / 1024))" \
      'BEGIN { printf "made: check %.1f s, %d KB", f - s, kb }')
  fi
  statuses+=("$status")
  printf '%-28s %s\n' "$name" "$status"
}

# steps_shot NAME INPUT "what to look for" COMMAND...: runs each COMMAND (tpmsfill's subcommand
# and arguments, or `cp FROM TO`) in $work, the last one leaving NAME.png there, which goes to
# OUT_DIR. The page shows the commands as given, each prefixed by tpmsfill. A step already run
# for an earlier image (the same model fit) is not run again: its outputs are still there.
declare -A steps_run=()
steps_shot() {
  local name=$1 input=$2 note=$3 shown="" step code=0
  shift 3
  for step in "$@"; do
    [[ "$step" == cp\ * ]] && shown+="$step"$'\n' || shown+="tpmsfill $step"$'\n'
  done
  names+=("$name") fill_commands+=("${shown%$'\n'}") render_commands+=("") notes+=("$note")
  local status=""
  held_back "$name" "$input" && return 0
  local t0 t1
  t0=$(now)
  for step in "$@"; do
    [[ -z "${steps_run[$step]:-}" ]] || continue
    steps_run[$step]=1
    # shellcheck disable=SC2086  # the steps are words
    if [[ "$step" == cp\ * ]]; then
      (cd "$work" && $step) 2>"$work/$name.err" || code=$?
    else
      (cd "$work" && "$tpmsfill" $step --quiet) 2>"$work/$name.err" || code=$?
    fi
    ((code == 0)) || break
  done
  t1=$(now)
  if ((code != 0)); then
    status="FAILED (exit $code): $(grep -v warning "$work/$name.err" | head -n 1)"
  else
    mv "$work/$name.png" "$out_dir/$name.png"
    status=$(awk -v f="$t1" -v s="$t0" -v kb="$(($(stat -c %s "$out_dir/$name.png") / 1024))" \
      'BEGIN { printf "made: %.1f s, %d KB", f - s, kb }')
  fi
  statuses+=("$status")
  printf '%-28s %s\n' "$name" "$status"
}

# --- the features, one function each ------------------------------------------------------------

types=(primitive gyroid diamond iwp neovius frd lidinoid splitp)

image_types() {
  local t
  for t in "${types[@]}"; do
    shot "types-network-$t" cube10.off "" "--lattice $t --cell 5 --voxel 0.1" \
      "the $t network: solid struts around one side of the surface"
    shot "types-sheet-$t" cube10.off "" "--lattice $t --sheet --cell 5 --voxel 0.1" \
      "the $t sheet: a wall along the minimal surface, open on both sides"
  done
}

image_porosity() {
  local p
  for p in 0.5 0.7 0.85; do
    shot "porosity-$p" cube10.off "" "--lattice gyroid --cell 5 --voxel 0.1 --porosity $p" \
      "porosity $p: the level is solved so that $(awk -v p="$p" 'BEGIN { print 100 * p }') % of the cube is void"
  done
}

image_field() {
  if ((have_skull)); then
    shot field-skull cube20.off "--clip x 10" "--field skull.itdf --voxel 0.1" \
      "the skull CT's bone (values above 2.9, fitted with 32³ coefficients) stretched over the 20 mm cube and cut open at x = 10 mm: the cranium's wall, the orbits and the jaw, from 128 KiB of coefficients"
  fi
  shot field-sponge cube20.off "" "--field sponge.itdf --porosity 0.6 --voxel 0.1" \
    "a sponge: solid outside 40 random overlapping spherical pores, t1 <= C with t1 set for a porosity of 0.6"
  shot field-sponge-sheet cube20.off "" "--field sponge-sheet.itdf --voxel 0.1" \
    "the same field as a surface type: a 0.5 mm sheet along C = 0.05, the boundary of the pores grown until most of them meet, open to both sides"
}

image_rotation() {
  shot rotation cube10.off "" "--lattice gyroid --cell 5 --voxel 0.1 --rotate 0 0 45" \
    "the same gyroid turned 45° about z: the channels now run diagonally across the faces"
}

image_grade_linear() {
  shot grade-linear cube20.off "" \
    "--lattice gyroid --cell 2.5 --voxel 0.1 --grade porosity 0.85 0.5 --grade-along z" \
    "porosity from 0.85 at the bottom to 0.5 at the top: the struts thicken upwards"
}

image_grade_radial() {
  shot grade-radial cylinder.off "--view 35 50" \
    "--lattice gyroid --cell 2.5 --voxel 0.1 --grade porosity 0.85 0.5 --grade-along radial-z --grade-range 0 10" \
    "porosity from 0.85 on the axis to 0.5 at the rim: the top face shows open centre, dense ring"
}

image_grade_depth() {
  shot grade-depth femur.off "--view -80 -160 --clip x -1" \
    "--scale 35 --lattice gyroid --cell 2 --voxel 0.1 --grade porosity 0.5 0.85 --grade-along depth --grade-range 0 3" \
    "cut open along the bone: dense (porosity 0.5) at the surface, open (0.85) from 3 mm deep"
}

image_grade_cell() {
  shot grade-cell cube20.off "" \
    "--lattice gyroid --cell 3 --voxel 0.1 --grade cell 3 6 --grade-along x" \
    "cells growing from 3 mm to 6 mm along x, left to right on the front face"
}

image_skin() {
  shot skin femur.off "--view -80 -160 --clip x -1" \
    "--scale 35 --lattice gyroid --cell 2 --voxel 0.1 --skin 0.5" \
    "cut open along the bone: a closed 0.5 mm shell around the gyroid core"
}

image_femur_gyroid() {
  shot femur-gyroid femur.off "--view 0 -160" "--scale 35 --lattice gyroid --cell 2 --voxel 0.1" \
    "the main job: the 35 mm femur filled with 2 mm gyroid cells, clipped to the bone's surface"
}

# Seed 004: lattice layers that follow a surface (tpmsfill conformal), on its four
# demonstrations: a dome, a wave, a face and a turbine blade (a tube, with two ring regions).
image_conformal() {
  [[ -e "$work/docs" ]] || ln -s "$PWD/docs" "$work/docs"
  shot_command=conformal
  shot conformal-hemisphere hemisphere.off "--view -60 -120" \
    "--height 3 --lattice primitive --cell 5 --voxel 0.3" \
    "a 3 mm Schwarz P layer (5 mm cells, the seed's main region) on a 30 mm dome: cells keep their size on average, stretched towards the rim by the layout (area scale p5-p95 about 0.5-1.5)"
  shot conformal-wave wave.off "--view -30 45" \
    "--height 3 --lattice gyroid --cell 5 --voxel 0.3 --skins 0.4 0" \
    "a 3 mm gyroid layer on a wavy 80 mm panel with a 0.4 mm skin on the surface: over crests, troughs and saddles alike"
  shot conformal-face nefertiti.off "--view 0 -90" \
    "--scale 20 --height 3 --lattice primitive --cell 5 --voxel 0.3" \
    "Debian's Nefertiti (CGAL's own parameterization example, scaled to 97 mm) under a 3 mm Schwarz P layer: the seed's face, where curvature changes fastest"
  shot conformal-blade blade.off "--view -15 25" \
    "--scale 2.5 --height 4 --recipe docs/recipes/conformal/blade-rings.json --voxel 0.4" \
    "Debian's turbine blade scaled to 323 mm (a tube, cut along a seam the lattice closes across) under a 4 mm Schwarz P layer of 5 mm cells, with an I-WP region near the root and a gyroid region at mid-span (docs/recipes/conformal/blade-rings.json)"
  shot_command=fill
}

# A messy scan's defects (issue 17): Debian's elephant with holes, `check --picture`.
image_check() {
  if [[ -f "$femur_tarball" ]]; then
    tar -xzf "$femur_tarball" -C "$work" --strip-components=2 \
      data/meshes/elephant-with-holes.off 2>/dev/null || true
  fi
  check_shot check-elephant elephant-with-holes.off "--view z" \
    "Debian's elephant with holes, as a scan comes: each hole's rim drawn in the border colour, thick and over the surface, paler where the body hides it; the legend counts every defect class"
}

# Seed 001 (issue 18): Debian's bunny as a 10 mm solid (--units cm) whose material is the
# distance to a point by its front paws, fitted once (`material fit`, about 20 s), then sliced
# directly with the material in colour, cut into surfaces of equal material, and filled with a
# gyroid whose porosity follows the material.
image_material() {
  local fit="material fit bunny00.off bunny.tsm --units cm --material point -3 -4.5 0"
  steps_shot material-slice bunny00.off \
    "a layer through the middle of the bunny (z = 0 to 0.5 mm), sliced from the splines without a mesh: each point coloured by its material, the distance to a point by the front paws (blue near, yellow far); the ear whole to its tip, since the fit keeps G fold-free (issue 40; it was lost before, where G folded)" \
    "$fit" \
    "material slice bunny.tsm layers --layer 0.5 --start 0 --format png --colour --pixel 0.03" \
    "cp layers/layer_00000.png material-slice.png"
  steps_shot material-iso bunny00.off \
    "the surfaces where the material is 3, 5, 7 and 9 mm: nested shells around the point, open where they meet the bunny's surface (their back faces in the warm tint)" \
    "$fit" \
    "material iso bunny.tsm iso.ply --values 3 5 7 9" \
    "render iso.ply material-iso.png --view z --size 480"
  steps_shot material-graded bunny00.off \
    "a gyroid whose porosity follows the material, 0.3 near the point to 0.9 far from it, cut open at z = 0: the walls thin from the paws to the back" \
    "$fit" \
    "fill bunny00.off graded.stl --units cm --cell 1.2 --voxel 0.04 --grade porosity 0.3 0.9 --grade-by bunny.tsm" \
    "render graded.stl material-graded.png --view z --clip z 0 --size 480"
}

# >>> HYBRID RECIPES SLOT: every docs/recipes/*.json, filled into the 20 mm cube, image named
# >>> after the recipe. The fill gets only --recipe and --voxel: lattice types, cells and the
# >>> blend region come from the recipe.
image_recipes() {
  local recipe name note
  [[ -e "$work/docs" ]] || ln -s "$PWD/docs" "$work/docs"
  for recipe in docs/recipes/*.json; do
    [[ -f "$recipe" ]] || continue
    name=$(basename "$recipe" .json)
    # The recipe's "description", if it has one, is the sentence under the picture.
    note=$(sed -n 's/.*"description"[[:space:]]*:[[:space:]]*"\([^"]*\)".*/\1/p' "$recipe" | head -n 1)
    shot "$name" cube20.off "" "--recipe $recipe --voxel 0.1" \
      "${note:-the hybrid lattice of $recipe}"
  done
}
# <<< HYBRID RECIPES SLOT

# Seed 004's Fig. 4 (a 20 mm plate) and Fig. 7 (a 40 mm plate) from docs/recipes/seed004, seen
# from above, and Fig. 9's blade (a 4 mm layer on Debian's blade); the sentence under each is the
# recipe's description, which gives the seed's.
image_seed004() {
  local recipe name note plate
  [[ -e "$work/docs" ]] || ln -s "$PWD/docs" "$work/docs"
  for recipe in docs/recipes/seed004/*.json; do
    [[ -f "$recipe" ]] || continue
    name=seed004-$(basename "$recipe" .json)
    plate=plate20.off
    [[ "$name" == *fig7* ]] && plate=plate40.off
    note=$(sed -n 's/.*"description"[[:space:]]*:[[:space:]]*"\([^"]*\)".*/\1/p' "$recipe" | head -n 1)
    if [[ "$name" == *fig9* ]]; then  # the blade of Fig. 9: a layer on Debian's blade
      shot_command=conformal
      shot "$name" blade.off "--view -15 25" "--scale 2.5 --height 4 --recipe $recipe --voxel 0.3" \
        "${note:-$recipe}"
      shot_command=fill
      continue
    fi
    shot "$name" "$plate" "--view z" "--recipe $recipe --voxel 0.1" "${note:-$recipe}"
  done
}

features=(image_types image_porosity image_rotation image_grade_linear image_grade_radial
  image_grade_depth image_grade_cell image_skin image_femur_gyroid image_field image_conformal
  image_material image_check image_recipes image_seed004)
for feature in "${features[@]}"; do "$feature"; done

# --- the page ----------------------------------------------------------------------------------

index_of() {
  local i
  for i in "${!names[@]}"; do [[ "${names[$i]}" == "$1" ]] && { echo "$i"; return; }; done
  echo "catalogue: no image named $1" >&2
  exit 1
}
picture() {  # markdown for NAME's picture, or a note that it is not made yet
  if [[ -f "$out_dir/$1.png" ]]; then echo "![$1](${link_prefix}$1.png)"; else echo "*(pending)*"; fi
}
commands() {  # the commands behind NAME, as a shell block
  local i
  i=$(index_of "$1")
  if [[ -n "${render_commands[$i]}" ]]; then
    printf '```\n%s\n%s\n```\n' "${fill_commands[$i]}" "${render_commands[$i]}"
  else
    printf '```\n%s\n```\n' "${fill_commands[$i]}"
  fi
}
section() {  # section TITLE NAME: picture, commands, what to look for
  local i note
  i=$(index_of "$2")
  note=${notes[$i]%.}  # one full stop, whether or not the note brought its own
  printf '## %s\n\n%s\n\n%s\n\n%s.\n\n' "$1" "$(picture "$2")" "$(commands "$2")" \
    "$(tr '[:lower:]' '[:upper:]' <<<"${note:0:1}")${note:1}"
}
types_table() {  # types_table TYPE...: one column per type, network row and sheet row
  local t
  printf '|'; for t in "$@"; do printf ' | %s' "$t"; done; printf ' |\n'
  printf '|---'; for t in "$@"; do printf '|:---:'; done; printf '|\n'
  for style in network sheet; do
    printf '| %s' "$style"; for t in "$@"; do printf ' | %s' "$(picture "types-$style-$t")"; done
    printf ' |\n'
  done
}

tmp_page="$page.tmp"
{
  cat <<'EOF'
# Lattice catalogue

One picture per lattice feature, each a real `tpmsfill fill` output rendered by
`tpmsfill render` (orthographic, 2×2 supersampled; where the mesh is cut open with
`--clip`, the cut is drawn flat in a darker, warmer tint). Every picture is made by
[`scripts/catalogue.sh`](../scripts/catalogue.sh), which builds, writes the inputs, runs the
commands shown under each picture and writes this page:

```
bash scripts/catalogue.sh                  # all images into docs/images, this page
bash scripts/catalogue.sh docs/images 'grade-*'   # only some
```

Inputs, written by the script: `cube10.off` and `cube20.off`, cubes of 10 and 20 mm from the
origin (12 triangles each); `cylinder.off`, radius 10 mm around the z axis, 20 mm high; and
`femur.off`, the proximal femur Debian's `libcgal-demo` ships, made 35 mm long by `--scale 35`
(its head is at −z, so its views look from below with −z up). Pictures marked *(pending)* need
an option this build of tpmsfill does not have yet.

## Lattice types

Eight triply periodic minimal surfaces in the 10 mm cube with 5 mm cells: the network (solid on
one side of the surface) above, the sheet (a wall of `--thickness`, default 0.3 mm, along it)
below.

EOF
  types_table "${types[@]:0:4}"
  echo
  types_table "${types[@]:4}"
  cat <<'EOF'

```
tpmsfill fill cube10.off types-network-TYPE.stl --lattice TYPE --cell 5 --voxel 0.1
tpmsfill fill cube10.off types-sheet-TYPE.stl --lattice TYPE --sheet --cell 5 --voxel 0.1
tpmsfill render types-network-TYPE.stl types-network-TYPE.png --size 480
```

Look for each surface's symmetry: primitive's straight channels along the axes, the gyroid's
helical channels, diamond's tetrahedral struts, and the thin sheet of each.

## Porosity

EOF
  printf '| porosity 0.5 | porosity 0.7 | porosity 0.85 |\n|:---:|:---:|:---:|\n'
  printf '| %s | %s | %s |\n\n' "$(picture porosity-0.5)" "$(picture porosity-0.7)" \
    "$(picture porosity-0.85)"
  commands porosity-0.7
  cat <<'EOF'

`--porosity P` solves the level (network) or the wall thickness (sheet) so that the fraction P
of the part is void: the struts thin from left to right while the cell stays 5 mm.

EOF
  section "Rotation" rotation
  section "Grading: linear" grade-linear
  section "Grading: radial" grade-radial
  section "Grading: with depth below the surface" grade-depth
  section "Grading: cell size" grade-cell
  section "Skin" skin
  section "The femur" femur-gyroid
  cat <<'TEXT'
## Porous structures from a scanned field (Lin & Gao)

A discrete field fitted by an implicit B-spline and stored as ITDF (`tpmsfill field fit`), then
put into the model by `fill --field`: solid type t1 ≤ C ≤ t2 on the left two, surface type on
the right. The ITDF files are made in the script from Debian's skull CT and a generated sponge
field: `tpmsfill field fit skull_2.9.inr skull.itdf --coefficients 32 --solid 2.9 inf`.

TEXT
  printf '| skull CT, solid | sponge, solid | sponge, sheet |\n|:---:|:---:|:---:|\n'
  printf '| %s | %s | %s |\n\n' "$(picture field-skull)" "$(picture field-sponge)" \
    "$(picture field-sponge-sheet)"
  for name in field-skull field-sponge field-sponge-sheet; do
    if [[ " ${names[*]} " == *" $name "* ]]; then
      commands "$name"
      i=$(index_of "$name")
      printf '\n%s.\n\n' "$(tr '[:lower:]' '[:upper:]' <<<"${notes[$i]:0:1}")${notes[$i]:1}"
    fi
  done
  cat <<'TEXT'
## Layers that follow a surface (Yang et al. 2023)

`tpmsfill conformal`: a surface laid flat by mean-value coordinates, a slab design carried onto
it through the field, filled and validated like any part (docs/method.md). The four surfaces
of the seed's demonstrations: a dome and a wave (made by `scripts/surfaces.py`), a face and a
turbine blade (Debian's libcgal-demo).

TEXT
  printf '| dome | wave |\n|:---:|:---:|\n| %s | %s |\n' "$(picture conformal-hemisphere)" \
    "$(picture conformal-wave)"
  printf '| **face** | **blade** |\n| %s | %s |\n\n' "$(picture conformal-face)" \
    "$(picture conformal-blade)"
  for name in conformal-hemisphere conformal-wave conformal-face conformal-blade; do
    commands "$name"
    i=$(index_of "$name")
    printf '\n%s.\n\n' "$(tr '[:lower:]' '[:upper:]' <<<"${notes[$i]:0:1}")${notes[$i]:1}"
  done
  cat <<'TEXT'
## Materials through a solid (Li & Fu 2021)

A solid and a material through it as two trivariate splines (`tpmsfill material fit`), then
used without a mesh of the solid: printer layers with their material (`material slice`, here
`--colour` for people; printers get grey = material), surfaces of equal material (`material
iso`), and a lattice graded by the material (`fill --grade-by`). Debian's bunny, 10 mm.

TEXT
  printf '| slice, coloured by material | equal-material surfaces | graded gyroid |\n|:---:|:---:|:---:|\n'
  printf '| %s | %s | %s |\n\n' "$(picture material-slice)" "$(picture material-iso)" \
    "$(picture material-graded)"
  for name in material-slice material-iso material-graded; do
    commands "$name"
    i=$(index_of "$name")
    printf '\n%s.\n\n' "$(tr '[:lower:]' '[:upper:]' <<<"${notes[$i]:0:1}")${notes[$i]:1}"
  done
  section "A messy scan, checked: check --picture" check-elephant
  hybrids=()
  for i in "${!names[@]}"; do
    [[ "${fill_commands[$i]}" == *--recipe* ]] && hybrids+=("${names[$i]}")
  done
  if ((${#hybrids[@]})); then
    printf '## Hybrid lattices\n\nTwo lattice types blended across a region, from the recipes in `docs/recipes/`.\n\n'
    for name in "${hybrids[@]}"; do section "$name" "$name"; done
  fi
} >"$tmp_page"
mv "$tmp_page" "$page"

# --- what was made -------------------------------------------------------------------------------

echo
echo "| image | status |"
echo "|---|---|"
for i in "${!names[@]}"; do
  [[ "${statuses[$i]}" == "not selected" ]] && continue
  echo "| ${names[$i]} | ${statuses[$i]} |"
done
echo
echo "page: $page; images: $out_dir"
failed=0
for s in "${statuses[@]}"; do [[ "$s" == FAILED* ]] && failed=1; done
exit $failed
