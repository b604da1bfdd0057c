  ! x = mantissa 2^exponent, 1/2 <= |mantissa| < 1 (frexp); 0, inf and NaN are their own mantissa
  pure function frexp_mantissa(x) result(m)
    real(c_double), intent(in) :: x
    real(c_double) :: m
    m = x
    if (ieee_is_finite(x) .and. abs(x) > 0.0_c_double) m = fraction(x)
  end function frexp_mantissa

  ! the exponent of x (0 for 0, inf and NaN), as a real
  pure function frexp_exponent(x) result(e)
    real(c_double), intent(in) :: x
    real(c_double) :: e
    e = 0.0_c_double
    if (ieee_is_finite(x) .and. abs(x) > 0.0_c_double) e = real(exponent(x), c_double)
  end function frexp_exponent

  ! x 2^e for a whole number e held in a real
  pure function times_power_of_two(x, e) result(y)
    real(c_double), intent(in) :: x, e
    real(c_double) :: y
    y = x
    if (ieee_is_finite(x) .and. abs(x) > 0.0_c_double) y = scale(x, int(e))
  end function times_power_of_two

  ! a b - fl(a b), exactly (Dekker's product, Veltkamp's splitting; |a|, |b| < 2^995)
  pure function two_product_error(a, b) result(err)
    real(c_double), intent(in) :: a, b
    real(c_double) :: err, prod, ta, ah, al, tb, bh, bl
    prod = a * b
    ta = 134217729.0_c_double * a
    ah = ta - (ta - a)
    al = a - ah
    tb = 134217729.0_c_double * b
    bh = tb - (tb - b)
    bl = b - bh
    err = ((ah * bh - prod) + ah * bl + al * bh) + al * bl
  end function two_product_error

  ! a + b - fl(a + b), exactly (Knuth's two-sum)
  pure function two_sum_error(a, b) result(err)
    real(c_double), intent(in) :: a, b
    real(c_double) :: err, s, bb
    s = a + b
    bb = s - a
    err = (a - (s - bb)) + (b - bb)
  end function two_sum_error
