// A column with an arm leaving its side at mid-height and curving out through 80 degrees.
union() {
  cylinder(h = 40, r = 5, $fn = 40);
  translate([30, 0, 12]) rotate([90, 0, 0]) rotate([0, 0, 100]) rotate_extrude(angle = 80, $fn = 120) translate([30, 0]) circle(r = 4.5, $fn = 36);
}
