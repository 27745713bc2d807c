! Error path: ppohDEM_integrate_system before ppohDEM_pre.
program dem_before_pre
    use ppohDEM_util
    implicit none
    type(ppohDEM_parameters) :: parameters
    type(ppohDEM_particles) :: particles
    type(ppohDEM_cells) :: cells
    type(ppohDEM_walls) :: walls
    type(ppohDEM_objects) :: objects
    call ppohDEM_integrate_system(parameters, particles, cells, walls, objects)
end program
