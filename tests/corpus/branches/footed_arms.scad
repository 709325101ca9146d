// A column with three arms at 120 degrees of azimuth, each curving out through 70 degrees,
// standing on a round foot (a flange wider than the column).
R = 25;
union() {
  cylinder(h = 4, r = 14, $fn = 64);
  cylinder(h = 30, r = 6, $fn = 48);
  for (a = [0, 120, 240]) rotate([0, 0, a]) translate([R, 0, 18]) rotate([90, 0, 0]) rotate([0, 0, 110]) rotate_extrude(angle = 70, $fn = 100) translate([R, 0]) circle(r = 4, $fn = 32);
}
