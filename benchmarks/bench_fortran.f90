program bench_fortran
end program bench_fortran
