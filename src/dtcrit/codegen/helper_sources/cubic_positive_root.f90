  ! Smallest (largest when `largest`) positive real root of t^3 + a2 t^2 + a1 t + a0; 0 when
  ! there is none.  Viete's trigonometric form when the three roots are real, the hyperbolic
  ! forms of Cardano's formula otherwise, then three Newton steps and two Newton steps with a
  ! compensated residual.
  pure function cubic_positive_root(a2, a1, a0, largest) result(t)
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_positive_inf
    real(c_double), intent(in) :: a2, a1, a0
    logical, intent(in) :: largest
    real(c_double) :: t
    real(c_double), parameter :: pi = 3.141592653589793_c_double
    real(c_double) :: shift, p, q, r, arg, phi, s3, u, one, g, dg, big
    real(c_double) :: s, c, pr, pe, sm, bb, se, sh, sl, th, tl
    real(c_double) :: cand(3), coef(3)
    integer :: n, j, k
    shift = a2 / 3.0_c_double
    p = a1 - a2 * shift
    q = (2.0_c_double * shift * shift - a1) * shift + a0
    n = 0
    if (p < 0.0_c_double .and. q * q / 4.0_c_double + p * p * p / 27.0_c_double <= 0.0_c_double) then
      r = 2.0_c_double * sqrt(-p / 3.0_c_double)
      arg = 0.0_c_double
      if (r > 0.0_c_double) arg = 4.0_c_double * q / (r * r * r)
      arg = max(-1.0_c_double, min(1.0_c_double, arg))
      phi = acos(-arg) / 3.0_c_double
      do j = 0, 2
        n = n + 1
        cand(n) = r * cos(phi - 2.0_c_double * pi * real(j, c_double) / 3.0_c_double) - shift
      end do
    else
      s3 = sqrt(abs(p) / 3.0_c_double)
      if (p > 0.0_c_double) then
        one = -2.0_c_double * s3 * sinh(asinh(1.5_c_double * q / (p * s3)) / 3.0_c_double)
      else if (p < 0.0_c_double) then
        u = max(1.0_c_double, 1.5_c_double * abs(q) / (-p * s3))
        one = -2.0_c_double * sign(1.0_c_double, q) * s3 * cosh(acosh(u) / 3.0_c_double)
        if (q == 0.0_c_double) one = 0.0_c_double
      else
        one = -sign(abs(q)**(1.0_c_double / 3.0_c_double), q)
      end if
      n = 1
      cand(1) = one - shift
    end if
    big = ieee_value(big, ieee_positive_inf)
    if (largest) then
      t = -big
    else
      t = big
    end if
    do j = 1, n
      if (cand(j) > 0.0_c_double) then
        if (largest .and. cand(j) > t) t = cand(j)
        if (.not. largest .and. cand(j) < t) t = cand(j)
      end if
    end do
    do k = 1, 3
      g = ((t + a2) * t + a1) * t + a0
      dg = (3.0_c_double * t + 2.0_c_double * a2) * t + a1
      if (ieee_is_finite(t) .and. dg /= 0.0_c_double) t = t - g / dg
    end do
    ! two more Newton steps with the residual from compensated Horner (Dekker's error-free
    ! product with Veltkamp splitting, error-free sums)
    do k = 1, 2
      if (.not. ieee_is_finite(t)) exit
      coef = [a2, a1, a0]
      s = 1.0_c_double
      c = 0.0_c_double
      do j = 1, 3
        pr = s * t
        sh = 134217729.0_c_double * s
        sh = sh - (sh - s)
        sl = s - sh
        th = 134217729.0_c_double * t
        th = th - (th - t)
        tl = t - th
        pe = ((sh * th - pr) + sh * tl + sl * th) + sl * tl
        sm = pr + coef(j)
        bb = sm - pr
        se = (pr - (sm - bb)) + (coef(j) - bb)
        s = sm
        c = c * t + (pe + se)
      end do
      dg = (3.0_c_double * t + 2.0_c_double * a2) * t + a1
      if (dg /= 0.0_c_double) t = t - (s + c) / dg
    end do
    if (.not. ieee_is_finite(t)) t = 0.0_c_double
  end function cubic_positive_root
