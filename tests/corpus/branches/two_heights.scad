// A column on a round foot with two arms at different heights and azimuths, each curving out
// and up through 70 degrees.
union() {
  cylinder(h = 4, r = 15, $fn = 64);
  cylinder(h = 46, r = 6, $fn = 48);
  for (p = [[0, 16, 22], [150, 30, 18]]) rotate([0, 0, p[0]]) translate([p[2], 0, p[1]]) rotate([90, 0, 0]) rotate([0, 0, 110]) rotate_extrude(angle = 70, $fn = 100) translate([p[2], 0]) circle(r = 4, $fn = 32);
}
