// Ruan Fig. 11's column splitting into two curved branches, other sizes: the +X arm starts inside
// the -X arm and leaves it sideways.
R = 35; rad = 5;
union() {
  cylinder(h = 25, r = rad, $fn = 48);
  for (s = [-1, 1]) translate([s * R, 0, 25]) rotate([90, 0, 0])
    rotate([0, 0, s > 0 ? 90 : 0]) rotate_extrude(angle = 70, $fn = 120)
      translate([R, 0]) circle(r = rad, $fn = 40);
}
