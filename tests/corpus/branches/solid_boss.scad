// A solid round bar (r 20, 50 tall) with a boss (r 7, bore 3.5) leaving its side 15 deg below the
// horizontal: a plane across the boss that cuts into the bar takes a solid slab of it, no film.
$fn = 48;
difference() {
  union() {
    cylinder(h = 50, r = 20);
    translate([0, 0, 22]) rotate([0, 105, 0]) cylinder(h = 34, r = 7);
  }
  translate([0, 0, 22]) rotate([0, 105, 0]) cylinder(h = 35, r = 3.5);
}
