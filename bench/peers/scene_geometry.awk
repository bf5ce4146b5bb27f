# The two flowing scenes of bench/run_scenes.sh (issue 21 (b), (c)), written once and read by
# every code: the walls as an ASCII STL and the starting particles as a LAMMPS data file
# (LIGGGHTS' read_data, atom_style granular) and as Quarry's particles CSV. Units SI.
#   awk -v scene=hopper|drum -v what=stl|data|csv -f scene_geometry.awk > FILE
# The scenes (spheres of d = 6 mm, 2500 kg/m³, on a 6.6 mm simple cubic lattice, jitter ±0.1 mm,
# at rest; the same jitter in every file: srand(seed) in one awk):
#   hopper  a flat-bottomed square bin 0.15 m wide and 0.25 m tall, a round outlet of D = 40 mm
#           in the middle of its floor (z = 0), open from the start; 22 × 22 × 21 = 10,164
#           spheres fill it to 0.14 m. Particles falling below z = -0.06 leave the domain.
#   drum    a closed cylinder of radius 0.1 m and length 0.2 m about the y axis through the
#           origin (rotated by the codes); the lattice sites inside r < 0.0955 m below z = 0.01.
BEGIN {
  srand(seed == "" ? 2021 : seed)
  pi = atan2(0, -1)
  d = 0.006; a = 0.0066; jit = 1.0e-4; rho = 2500
  if (scene == "hopper") {
    W = 0.15; H = 0.25; D = 0.04
    lo[1] = -0.085; hi[1] = 0.085; lo[2] = -0.085; hi[2] = 0.085; lo[3] = -0.06; hi[3] = 0.26
  } else if (scene == "drum") {
    R = 0.1; L = 0.2
    lo[1] = -0.11; hi[1] = 0.11; lo[2] = -0.11; hi[2] = 0.11; lo[3] = -0.11; hi[3] = 0.11
  } else { print "scene_geometry.awk: scene=hopper|drum" > "/dev/stderr"; exit 2 }
  if (what == "stl") { stl(); exit 0 }
  if (what != "data" && what != "csv") { print "scene_geometry.awk: what=stl|data|csv" > "/dev/stderr"; exit 2 }
  lattice()
  if (what == "csv") {
    print "x,y,z,radius,type"
    for (i = 1; i <= n; ++i) printf "%.17g,%.17g,%.17g,%.17g,grain\n", px[i], py[i], pz[i], d / 2
  } else {
    print "LAMMPS data file: bench/peers/scene_geometry.awk scene " scene
    print ""
    print n " atoms"
    print "1 atom types"
    print ""
    printf "%.17g %.17g xlo xhi\n%.17g %.17g ylo yhi\n%.17g %.17g zlo zhi\n", lo[1], hi[1], lo[2], hi[2], lo[3], hi[3]
    print ""
    print "Atoms # granular: atom-ID atom-type diameter density x y z"
    print ""
    for (i = 1; i <= n; ++i) printf "%d 1 %.17g %.17g %.17g %.17g %.17g\n", i, d, rho, px[i], py[i], pz[i]
  }
}

function jitter() { return (2 * rand() - 1) * jit }

function site(x, y, z) { ++n; px[n] = x + jitter(); py[n] = y + jitter(); pz[n] = z + jitter() }

function lattice(   i, j, k, m, x, y, z, half, rmax) {
  n = 0
  if (scene == "hopper") {
    m = 22; half = (m - 1) / 2
    for (k = 0; k < 21; ++k) for (j = 0; j < m; ++j) for (i = 0; i < m; ++i)
      site((i - half) * a, (j - half) * a, 0.0035 + k * a)
  } else {
    m = 30; half = (m - 1) / 2; rmax = R - d / 2 - 0.0015
    for (k = -15; k <= 15; ++k) for (j = 0; j < m; ++j) for (i = -15; i <= 15; ++i) {
      x = i * a; z = k * a
      if (z < 0.01 && x * x + z * z < rmax * rmax) site(x, (j - half) * a, z)
    }
  }
}

function facet(ax, ay, az, bx, by, bz, cx, cy, cz,   ux, uy, uz, vx, vy, vz, nx, ny, nz, l) {
  ux = bx - ax; uy = by - ay; uz = bz - az; vx = cx - ax; vy = cy - ay; vz = cz - az
  nx = uy * vz - uz * vy; ny = uz * vx - ux * vz; nz = ux * vy - uy * vx
  l = sqrt(nx * nx + ny * ny + nz * nz); nx /= l; ny /= l; nz /= l
  printf "  facet normal %.9g %.9g %.9g\n    outer loop\n", nx, ny, nz
  printf "      vertex %.17g %.17g %.17g\n      vertex %.17g %.17g %.17g\n      vertex %.17g %.17g %.17g\n",
         ax, ay, az, bx, by, bz, cx, cy, cz
  print "    endloop\n  endfacet"
}

function stl(   k, M, t0, t1, c0, s0, c1, s1, h, q0, q1, y0, y1) {
  print "solid " scene
  if (scene == "hopper") {
    h = W / 2
    # Four side walls, normals inwards (the contact is two-sided; the orientation is cosmetic).
    facet(-h, -h, 0, h, -h, 0, h, -h, H); facet(-h, -h, 0, h, -h, H, -h, -h, H)
    facet(h, h, 0, -h, h, 0, -h, h, H);   facet(h, h, 0, -h, h, H, h, h, H)
    facet(-h, h, 0, -h, -h, 0, -h, -h, H); facet(-h, h, 0, -h, -h, H, -h, h, H)
    facet(h, -h, 0, h, h, 0, h, h, H);    facet(h, -h, 0, h, h, H, h, -h, H)
    # The floor: the ring between the outlet's circle and the square, M rays from the centre (M a
    # multiple of 8, so the square's corners are on rays); each ray meets the circle and the square.
    M = 64
    for (k = 0; k < M; ++k) {
      t0 = 2 * pi * k / M; t1 = 2 * pi * (k + 1) / M
      c0 = cos(t0); s0 = sin(t0); c1 = cos(t1); s1 = sin(t1)
      q0 = h / (abs(c0) > abs(s0) ? abs(c0) : abs(s0)); q1 = h / (abs(c1) > abs(s1) ? abs(c1) : abs(s1))
      facet(D / 2 * c0, D / 2 * s0, 0, q0 * c0, q0 * s0, 0, q1 * c1, q1 * s1, 0)
      facet(D / 2 * c0, D / 2 * s0, 0, q1 * c1, q1 * s1, 0, D / 2 * c1, D / 2 * s1, 0)
    }
  } else {
    M = 96; y0 = -L / 2; y1 = L / 2
    for (k = 0; k < M; ++k) {
      t0 = 2 * pi * k / M; t1 = 2 * pi * (k + 1) / M
      c0 = R * cos(t0); s0 = R * sin(t0); c1 = R * cos(t1); s1 = R * sin(t1)
      facet(c0, y0, s0, c0, y1, s0, c1, y1, s1); facet(c0, y0, s0, c1, y1, s1, c1, y0, s1)
      facet(0, y0, 0, c0, y0, s0, c1, y0, s1); facet(0, y1, 0, c1, y1, s1, c0, y1, s0)
    }
  }
  print "endsolid " scene
}

function abs(v) { return v < 0 ? -v : v }
