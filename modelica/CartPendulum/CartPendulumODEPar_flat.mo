class CartPendulumODEPar_flat
	parameter Real `m1` = 2. "Equivalent cart mass (kg)";
	parameter Real `d1` = 15. "Equivalent linear cart friction (N.s/m)";
	parameter Real `m2` = 1. "Pendulum mass (kg)";
	parameter Real `d2` = 0.5 "Rotational friction of the pendulum (N.m.s/rad)";
	parameter Real `l` = 0.5 "Pendulum length (m)";
	parameter Real `g` = 9.81 "Gravity (m/s2)";
	input Real `F` "Force on the cart (N)";
	output Real `y_x` "Measured cart position (m)";
	output Real `y_phi` "Measured pendulum angle (rad)";
	Real `x`(start=0.) "Cart position (m)";
	Real `phi`(start=0.) "Pendulum angle, 0 = hanging down (rad)";
	Real `v`(start=0.) "Cart velocity (m/s)";
	Real `w`(start=0.) "Pendulum angular velocity (rad/s)";
equation
	`y_phi` = `phi`;
	`y_x` = `x`;
	(((((`m2` * `l`) * cos(`phi`)) / 2.) * der(`v`)) + (((`m2` * (`l` ^ 2.)) / 3.) * der(`w`))) = ((((((- `m2`) * `g`) * `l`) * sin(`phi`)) / 2.) - (`d2` * `w`));
	(((`m1` + `m2`) * der(`v`)) + ((((`m2` * `l`) * cos(`phi`)) / 2.) * der(`w`))) = ((((((`m2` * `l`) * sin(`phi`)) * (`w` ^ 2.)) / 2.) - (`d1` * `v`)) + `F`);
	der(`phi`) = `w`;
	der(`x`) = `v`;
end CartPendulumODEPar_flat;
