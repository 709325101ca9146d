// A tuning fork (unseen part): a handle r 6, 25 mm tall, a half ring of radius 12 (bar r 5) opening
// upwards, and two prongs r 5 rising 35 mm from its ends.
union() {
  cylinder(h = 27, r = 6, $fn = 64);
  translate([0, 0, 37]) rotate([90, 0, 0]) rotate([0, 0, 180]) rotate_extrude(angle = 180, $fn = 120) translate([12, 0]) circle(r = 5, $fn = 48);
  for (s = [-1, 1]) translate([s * 12, 0, 37]) cylinder(h = 35, r = 5, $fn = 48);
}
