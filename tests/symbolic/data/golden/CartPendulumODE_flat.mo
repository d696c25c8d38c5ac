class CartPendulumODE_flat
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
	((((0.5 * cos(`phi`)) / 2.) * der(`v`)) + (0.08333333333333333 * der(`w`))) = ((((-4.905) * sin(`phi`)) / 2.) - (0.5 * `w`));
	((3. * der(`v`)) + (((0.5 * cos(`phi`)) / 2.) * der(`w`))) = (((((0.5 * sin(`phi`)) * (`w` ^ 2.)) / 2.) - (15. * `v`)) + `F`);
	der(`phi`) = `w`;
	der(`x`) = `v`;
end CartPendulumODE_flat;
