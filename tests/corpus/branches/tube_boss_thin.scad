// tube_boss with a slimmer boss (r 4, bore 2) lower down (22 mm) and 14 mm out of the tube,
// tessellated more finely.
$fn = 64;
difference() {
  union() {
    cylinder(h = 50, r = 20);
    translate([0, 0, 22]) rotate([0, 90, 0]) cylinder(h = 34, r = 4);
  }
  translate([0, 0, -1]) cylinder(h = 52, r = 17);
  translate([0, 0, 22]) rotate([0, 90, 0]) cylinder(h = 35, r = 2);
}
